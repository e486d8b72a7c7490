// Read-only tables: uniform texel buffers viewed as 32-bit words (R32_UINT, engine/vk/compute_kernel.h). On
// lavapipe a texel fetch at a lane-dependent index is one gather, where a storage-buffer load is a loop over
// the lanes with a branch each; on GPUs both are ordinary loads. A fetch past the end reads 0 (robust buffer
// access), as a storage-buffer load would.
#ifndef IBLX_LIB_TABLE
#define IBLX_LIB_TABLE

#define IBLX_TABLE(setIndex, bindingIndex, name) \
  layout(set = setIndex, binding = bindingIndex) uniform usamplerBuffer name

uint tableUint(usamplerBuffer table, uint i) { return texelFetch(table, int(i)).r; }
float tableFloat(usamplerBuffer table, uint i) { return uintBitsToFloat(texelFetch(table, int(i)).r); }
// Element i of a table of 2- or 4-word elements.
uvec2 tableUvec2(usamplerBuffer table, uint i) {
  return uvec2(texelFetch(table, int(2u * i)).r, texelFetch(table, int(2u * i + 1u)).r);
}
vec2 tableVec2(usamplerBuffer table, uint i) { return uintBitsToFloat(tableUvec2(table, i)); }
uvec4 tableUvec4(usamplerBuffer table, uint i) {
  int w = int(4u * i);
  return uvec4(texelFetch(table, w).r, texelFetch(table, w + 1).r, texelFetch(table, w + 2).r,
               texelFetch(table, w + 3).r);
}
vec4 tableVec4(usamplerBuffer table, uint i) { return uintBitsToFloat(tableUvec4(table, i)); }
#endif
