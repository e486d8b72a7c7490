// Tests of the heat maps (engine/analysis/heat_map.h): values at the scaled pixel positions, the masked grey,
// the colorbar and the errors for bad input.
#include "engine/analysis/heat_map.h"

#include "engine/analysis/palette.h"
#include "engine/core/error.h"
#include "tests/support/canvas_probes.h"

#include <doctest/doctest.h>

#include <limits>

using namespace iblx;
using namespace iblx::test;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST_CASE("heat map: values map to dark and bright at the scaled pixel positions, NaN is grey") {
  HeatMap map;
  map.title = "relative error";
  map.unit = "relative squared error";
  map.width = 4;
  map.height = 2;
  map.values = {1e-4, 1e-3, 1e-2, 1e-1, 1e0, kNaN, 5e-3, 1e-7};
  map.low = 1e-4;
  map.high = 1;
  const Canvas canvas = drawHeatMap(map);
  // 4x2 scales by 64 to 256x128; find the image through its top-left pixel (value 1e-4 -> colormap(0)).
  const Rgb8 darkest = colormap(0), brightest = colormap(1);
  int left = -1, top = -1;
  for (int y = 0; y < canvas.height() && left < 0; ++y)
    for (int x = 0; x < canvas.width(); ++x)
      if (canvas.at(x, y) == darkest) {
        left = x, top = y;
        break;
      }
  REQUIRE(left >= 0);
  const int zoom = 64;
  const auto cell = [&](int x, int y) {
    return canvas.at(left + x * zoom + zoom / 2, top + y * zoom + zoom / 2);
  };
  CHECK(cell(0, 0) == darkest);
  CHECK(canvas.at(left + zoom - 1, top + zoom - 1) == darkest);
  CHECK(canvas.at(left + zoom, top) != darkest);
  CHECK(cell(0, 1) == brightest);  // 1e0
  CHECK(luma(cell(0, 1)) > 200);
  CHECK(luma(cell(0, 0)) < 40);
  CHECK(cell(1, 1) == kMaskedGrey);            // NaN
  CHECK(cell(2, 0) == colormap(0.5));          // 1e-2 is half way in log space
  CHECK(cell(3, 1) == darkest);                // below low clamps
  CHECK(luma(cell(1, 0)) < luma(cell(2, 0)));  // 1e-3 < 1e-2
  CHECK(canvas.width() > 256);                 // room for the colorbar
  // The colorbar holds the whole map: its brightest and darkest colours appear right of the image.
  CHECK(countColor(canvas, brightest, left + 4 * zoom + 1, canvas.width()) > 0);

  HeatMap bad = map;
  bad.values.pop_back();
  CHECK_THROWS_AS(drawHeatMap(bad), Error);
  bad = map;
  bad.low = 0;
  CHECK_THROWS_AS(drawHeatMap(bad), Error);
}
