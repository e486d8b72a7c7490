// The colours of the data in the figures: a categorical palette for the series of a plot (also the viewer's
// convergence curves) and the colormap of the heat maps.
#pragma once

#include "engine/analysis/canvas.h"

#include <cstddef>

namespace iblx {

// A categorical palette of 10 distinguishable colors (Tableau 10), cycling.
Rgb8 paletteColor(std::size_t index);

// Our own dark-blue -> teal -> green -> yellow map (a smooth spline through six control points whose luma
// rises steadily); t is clamped to [0, 1]; NaN gives kMaskedGrey.
Rgb8 colormap(double t);
inline constexpr Rgb8 kMaskedGrey{128, 128, 128};

}  // namespace iblx
