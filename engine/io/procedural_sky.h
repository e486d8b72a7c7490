// The project's default environment map: an analytic lat-long sky with ground, horizon and a small, very
// bright sun, i.e. the "sun 10^4 times the sky in a few texels" hard case of docs/DESIGN.md §5 with no file to ship.
#pragma once

#include "engine/io/env_image.h"

namespace iblx {

struct ProceduralSkyOptions {
  int width = 256;
  int height = 128;
  // Sun direction: elevation above the horizon, azimuth = phi of the lat-long map (u = azimuth / 360).
  double sunElevationDegrees = 35.0;
  double sunAzimuthDegrees = 60.0;
  double sunAngularRadiusDegrees = 1.5;
  double sunRadiance = 2.0e4;  // mean of R, G, B inside the disc: about 10^4 times the sky
  // Soft glow (forward scattering) around the sun: peak added radiance and e-folding angle.
  double glowRadiance = 3.0;
  double glowAngularWidthDegrees = 6.0;
  int supersampling = 4;  // per axis, per texel: anti-aliases the sun's edge
};

// Deterministic (no random numbers): the same options give the same bits. Throws iblx::Error on invalid
// options.
EnvImage makeProceduralSky(const ProceduralSkyOptions& options = {});

}  // namespace iblx
