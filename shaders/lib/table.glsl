// Read-only tables: uniform texel buffers whose elements are 1, 2 or 4 32-bit words (R32 / R32G32 /
// R32G32B32A32_UINT views; engine/vk/compute_kernel.h, engine/sampling/technique_data.h). Read a table with
// the functions of its element width. On lavapipe a texel fetch at a lane-dependent index is one gather,
// where a storage-buffer load is a loop over the lanes with a branch each; on GPUs both are ordinary loads. A
// fetch past the end reads 0 (robust buffer access), as a storage-buffer load would.
#ifndef IBLX_LIB_TABLE
#define IBLX_LIB_TABLE

// Declares the table `name` with `words` 32-bit words per element. Its set and binding are the kernel
// assembler's (engine/scene/kernel_prelude.h): IBLX_SET_<name> and IBLX_BINDING_<name>_W<words>, defined only
// for the tables the kernel's builders provide at that width, so reading any other table fails to compile,
// naming it.
#define IBLX_TABLE(name, words) \
  layout(set = IBLX_SET_##name, binding = IBLX_BINDING_##name##_W##words) uniform usamplerBuffer name

// 1-word elements.
uint tableUint(usamplerBuffer table, uint i) { return texelFetch(table, int(i)).x; }
float tableFloat(usamplerBuffer table, uint i) { return uintBitsToFloat(texelFetch(table, int(i)).x); }
// 2-word elements.
uvec2 tableUvec2(usamplerBuffer table, uint i) { return texelFetch(table, int(i)).xy; }
vec2 tableVec2(usamplerBuffer table, uint i) { return uintBitsToFloat(texelFetch(table, int(i)).xy); }
// 4-word elements.
uvec4 tableUvec4(usamplerBuffer table, uint i) { return texelFetch(table, int(i)); }
vec4 tableVec4(usamplerBuffer table, uint i) { return uintBitsToFloat(texelFetch(table, int(i))); }

// Binary search over sorted 1-word entries: the largest i in [lo, lo + len) with table[base + i] <= value,
// lo itself when none is. Over a CDF (cdf[i] <= u < cdf[i + 1]) that is u's bin, and a bin of zero width is
// never chosen. With a constant len the trip count is constant and the loop unrolls.
int tableSearchFloat(usamplerBuffer table, uint base, int lo, int len, float value) {
  while (len > 1) {
    int halfLen = len >> 1;
    lo = tableFloat(table, base + uint(lo + halfLen)) <= value ? lo + halfLen : lo;
    len -= halfLen;
  }
  return lo;
}
uint tableSearchUint(usamplerBuffer table, uint lo, uint len, uint value) {
  while (len > 1u) {
    uint halfLen = len >> 1u;
    lo = tableUint(table, lo + halfLen) <= value ? lo + halfLen : lo;
    len -= halfLen;
  }
  return lo;
}
#endif
