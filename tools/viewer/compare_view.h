// The viewer's compare mode: two renders of one scene (methods, sequences or settings A and B) composed into
// one canvas: a split view with a divider, A | B side by side with their per-pixel error against the ground
// truth below, or A and B flipped in turn. The viewer composes on the GPU (display_kernel.h); this CPU
// composition is its reference, which the tests compare it with, and draws the canvas before anything is
// rendered.
#pragma once

#include "engine/geometry/gbuffer.h"
#include "engine/io/image_write.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace iblx::viewer {

enum class CompareView { Split, SideBySide, Flip };
inline constexpr const char* kCompareViewNames[] = {"split", "side", "flip"};

struct CompareFrame {
  const GBuffer* gbuffer = nullptr;
  std::span<const float> a, b;       // width*height*3 each; empty: not rendered yet (drawn grey)
  std::span<const float> reference;  // empty: none (no error row)
  DisplayTransform display;          // one transform for both, so that brightness compares
  bool background = true;            // the environment around the object, else the window's grey
  CompareView view = CompareView::Split;
  double divider = 0.5;  // Split: the fraction of the width that shows A
  bool showB = false;    // Flip: which one
};

struct CompareCanvas {
  int width = 0, height = 0;
  std::vector<std::uint8_t> bgra;
};

// Split: W x H, A left of column round(divider * W), B from it on, the divider column drawn white.
// SideBySide: 2W x H (A | B), or 2W x 2H with a reference: below each, its relative squared error
// (x - r)^2 / (r^2 + 0.01) per pixel on one log scale shared by both (four decades under the larger 99.5th
// percentile; background grey). Flip: W x H, A or B (with showB false and no B: the single view of one image).
CompareCanvas composeCompare(const CompareFrame& frame);

// The shared error scale of SideBySide: [high * 1e-4, high]; std::nullopt when no pixel has an error.
std::optional<double> sharedErrorHigh(const GBuffer& gbuffer, std::span<const float> a,
                                      std::span<const float> b, std::span<const float> reference);

}  // namespace iblx::viewer
