// The density the OT solver transports (solver.h): an environment's sampling density, integrated exactly
// over the cells of an n x n grid over the lat-long parameter square.
#pragma once

#include "engine/io/env_image.h"

#include <span>
#include <vector>

namespace iblx {

// Sampling density on an n x n grid over the lat-long parameter square, row-major, row = v (theta = pi v from
// +Y), column = u (phi = 2 pi u): the exact integral of the nearest-texel weight (mean RGB) over each cell
// with respect to solid angle (so sin(theta) is included), divided by the cell's parameter area, normalised
// to mean 1. An all-black image gives sin(theta) (uniform sphere). Throws iblx::Error on a bad image or on
// n < 1.
std::vector<double> otDensityFromEnv(const EnvImage& env, int n);
// The same from W*H texel weights (texelSamplingWeights, or the smooth part of an OtSunSplit).
std::vector<double> otDensityFromWeights(std::span<const double> weights, int width, int height, int n);

}  // namespace iblx
