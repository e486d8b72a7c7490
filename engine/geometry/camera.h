// The camera of docs/DESIGN.md §3 with an orbit and a zoom: orthographic, rotating about the origin. The default
// camera (orbit 0,0, zoom 1) is docs/DESIGN.md §3's exactly: it looks down -Z at the unit sphere, which fills the
// image.
#pragma once

#include "engine/core/sphere_mapping.h"

#include <glm/glm.hpp>

namespace iblx {

struct CameraSpec {
  double azimuthDeg = 0.0;    // rotation of the camera about +Y; 90 puts it on +X looking down -X
  double elevationDeg = 0.0;  // then towards +Y, in [-90, 90]; 90 puts it above the origin looking down -Y
  double zoom = 1.0;          // > 0: the image half-height covers 1/zoom world units
};

// Throws a SettingError (the orbit or the zoom, engine/core/setting.h) when a value is out of range or not
// finite.
void checkCamera(const CameraSpec& camera);

// The camera's orthonormal frame in world space: image x along `right`, image y along `up`; the camera looks
// along -back, so `back` is the direction towards the viewer (wo) for every object pixel.
struct CameraFrame {
  glm::dvec3 right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0}, back{0.0, 0.0, 1.0};
  double zoom = 1.0;

  // World direction of camera-space vector (x, y, z) = x right + y up + z back.
  glm::dvec3 toWorld(glm::dvec3 c) const { return c.x * right + c.y * up + c.z * back; }
  // Camera-space coordinates of world point p.
  glm::dvec3 toCamera(glm::dvec3 p) const { return {glm::dot(p, right), glm::dot(p, up), glm::dot(p, back)}; }
  // The world-space image-plane point that pixel ray `r` (pixelToImagePlane) meets, in camera x, y.
  CameraRay onPlane(CameraRay r) const { return {r.x / zoom, r.y / zoom}; }
  // What a background pixel shows: a pinhole at the origin with the image plane at distance 1 along -back, so
  // the vertical field of view is 90° at zoom 1 and narrows with the zoom like the object (display only).
  glm::dvec3 backgroundDirection(CameraRay r) const {
    const CameraRay p = onPlane(r);
    return glm::normalize(p.x * right + p.y * up - back);
  }
};

// Azimuth a about +Y, then elevation e towards +Y, applied to the default frame (+X, +Y, +Z):
// back = (cos e sin a, sin e, cos e cos a), right = (cos a, 0, -sin a), up = back x right.
inline CameraFrame cameraFrame(const CameraSpec& camera) {
  const double a = camera.azimuthDeg * kPi / 180.0, e = camera.elevationDeg * kPi / 180.0;
  const double ca = std::cos(a), sa = std::sin(a), ce = std::cos(e), se = std::sin(e);
  CameraFrame f;
  f.back = {ce * sa, se, ce * ca};
  f.right = {ca, 0.0, -sa};
  f.up = {-se * sa, ce, -se * ca};
  f.zoom = camera.zoom;
  return f;
}

// The shading tangent of iblx's objects, a deterministic field of the world normal n: +Y x n = (n.z, 0,
// -n.x), normalized, i.e. along the latitude circle about +Y (the analytic sphere's tangent), so an
// anisotropic BRDF's X axis follows circles about the world's up axis on every object. At the poles of that
// field (n within 1e-6 rad of ±Y, where it is undefined) it is +X made orthogonal to n.
inline glm::dvec3 tangentFromNormal(glm::dvec3 n) {
  const glm::dvec3 t(n.z, 0.0, -n.x);
  if (t.x * t.x + t.z * t.z < 1e-12) return glm::normalize(glm::dvec3(1.0, 0.0, 0.0) - n.x * n);
  return glm::normalize(t);
}

}  // namespace iblx
