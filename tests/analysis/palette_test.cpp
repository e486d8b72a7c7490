// Tests of the figures' colours (engine/analysis/palette.h): the colormap's luma and its masked grey.
#include "engine/analysis/palette.h"

#include "tests/support/canvas_probes.h"

#include <doctest/doctest.h>

#include <limits>

using namespace iblx;
using namespace iblx::test;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST_CASE("colormap: luma rises monotonically, NaN is the masked grey") {
  double previous = -1;
  for (int i = 0; i < 256; ++i) {
    const double l = luma(colormap(i / 255.0));
    CHECK(l > previous);
    previous = l;
  }
  CHECK(luma(colormap(0)) < 40);
  CHECK(luma(colormap(1)) > 200);
  CHECK(colormap(-5) == colormap(0));
  CHECK(colormap(7) == colormap(1));
  // Dark blue at the bottom, yellow at the top.
  CHECK(colormap(0).b > colormap(0).r);
  CHECK((colormap(1).r > 200 && colormap(1).g > 200 && colormap(1).b < 100));
  CHECK(colormap(kNaN) == kMaskedGrey);
  CHECK((kMaskedGrey.r == kMaskedGrey.g && kMaskedGrey.g == kMaskedGrey.b));
}
