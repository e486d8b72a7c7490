// MIS compensation for environment techniques (Karlík, Šik, Vévoda, Skřivan & Křivánek 2019, "MIS
// Compensation: Optimizing Sampling Techniques in Multiple Importance Sampling", §4: inside MIS with a BRDF
// technique, an env technique should sample max(p - mean(p), 0) rather than p, leaving the flat part of the
// map to the other technique). Used by `mis --mis-compensation`; never alone, since the compensated density
// is 0 wherever the map is at or below its mean.
#pragma once

#include "engine/io/env_image.h"

namespace iblx {

// The map whose sampling weight (the mean of R, G, B) is max(m - mu, 0) per texel, mu = the mean of m over
// the sphere (sum of m * solid angle / 4 pi), as grey texels; an excess within 1e-6 mu counts as 0. A map
// that would become black everywhere (a constant map) is returned unchanged: there is nothing to compensate,
// and the plain density stays valid.
EnvImage misCompensated(const EnvImage& image);

}  // namespace iblx
