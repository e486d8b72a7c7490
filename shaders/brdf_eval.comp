// Evaluates the scene's BRDF part at direction pairs in the local frame: values[i] = f(wi, wo) in 1/sr, for
// pairs[2i] = wi, pairs[2i+1] = wo. engine/render/brdf_tabulation.cpp runs it (iblx merl-synth, tests).
layout(local_size_x = 64) in;
layout(std430, set = 1, binding = 0) readonly buffer BrdfPairs { vec4 brdfPairs[]; };
layout(std430, set = 1, binding = 1) writeonly buffer BrdfValues { vec4 brdfValues[]; };
layout(push_constant) uniform BrdfEvalPush { uint pairCount; } brdfEvalPush;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= brdfEvalPush.pairCount) return;
  brdfValues[i] = vec4(brdfEval(brdfPairs[2u * i].xyz, brdfPairs[2u * i + 1u].xyz), 0.0);
}
