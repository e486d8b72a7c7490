// The shading point handed to strategies: an orthonormal frame and wo, all in the environment frame.
#ifndef IBLX_LIB_SHADING
#define IBLX_LIB_SHADING
struct Shading {
  vec3 n, t, b;  // frame: local +Z = n, +X = t, +Y = b
  vec3 wo;       // direction to the viewer
  vec3 woLocal;  // wo in the local frame
};

vec3 toLocal(Shading s, vec3 w) { return vec3(dot(w, s.t), dot(w, s.b), dot(w, s.n)); }
vec3 toWorld(Shading s, vec3 w) { return w.x * s.t + w.y * s.b + w.z * s.n; }
#endif
