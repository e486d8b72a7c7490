// The PNG figures of `iblx converge`: log-log error against spp and against time (one line per method and
// sequence, the band spanning the seeds) and per-pixel error heat maps of each method's final image.
#pragma once

#include "engine/geometry/gbuffer.h"
#include "engine/render/convergence_runner.h"

#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace iblx::cli {

// Writes mse_vs_spp.png, mse_vs_time.png, relmse_vs_spp.png and relmse_vs_time.png into `dir`; returns the
// file names written. A reference with noise (Monte Carlo) adds its level as a grey dashed floor: errors near
// it are not resolved.
std::vector<std::string> writeConvergencePlots(const std::filesystem::path& dir,
                                               const std::string& sceneTitle,
                                               std::span<const ConvergenceRun> runs,
                                               const ReferenceNoise& noise = {});

// One heat map per final image, heat-NN-<method>-<sequence>.png, of the per-pixel relative squared error on a
// log scale shared by all of them; returns the file names written.
std::vector<std::string> writeErrorHeatMaps(const std::filesystem::path& dir, const GBuffer& gbuffer,
                                            std::span<const ConvergenceImage> images,
                                            std::span<const float> reference);

// The reference and each method's final image (first seed) as PNGs under one display transform, the
// reference's (automatic exposure, ACES), so that their brightness compares: reference.png and
// final-NN-<method>-<sequence>.png. Returns the file names written, the reference first.
std::vector<std::string> writeFinalImages(const std::filesystem::path& dir, const GBuffer& gbuffer,
                                          std::span<const ConvergenceImage> images,
                                          std::span<const float> reference);

// The captions of writeFinalImages' and writeErrorHeatMaps' images: "method/sequence at N spp, T s".
std::string imageCaption(const ConvergenceImage& image);

}  // namespace iblx::cli
