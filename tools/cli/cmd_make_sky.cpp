// `iblx make-sky`: writes the procedural sky (engine/io/procedural_sky) that ships as assets/default_sky.exr.
#include "engine/io/image_write.h"
#include "engine/io/procedural_sky.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/command_support.h"
#include "tools/cli/commands.h"

#include <algorithm>
#include <cstdio>

namespace iblx::cli {

int cmdMakeSky(const Args& args) {
  ProceduralSkyOptions options;
  std::string out = "sky.exr";
  ArgParser parser("make-sky");
  parser.value("--out", "FILE", "output .exr (default sky.exr)", [&](const std::string& v) { out = v; });
  parser.value("--size", "WxH", "map size (default 256x128)",
               [&](const std::string& v) { parseSize("--size", v, options.width, options.height); });
  parser.value("--sun-elevation", "DEG", "sun elevation above the horizon (default 35)",
               [&](const std::string& v) {
                 options.sunElevationDegrees = parseDouble("--sun-elevation", v, -90, 90);
               });
  parser.value("--sun-azimuth", "DEG", "sun azimuth phi (default 60)", [&](const std::string& v) {
    options.sunAzimuthDegrees = parseDouble("--sun-azimuth", v, -360, 360);
  });
  parser.value("--sun-radius", "DEG", "angular radius of the sun disc (default 1.5)",
               [&](const std::string& v) {
                 options.sunAngularRadiusDegrees = parseDouble("--sun-radius", v, 0.01, 45);
               });
  parser.value(
      "--sun-radiance", "L", "radiance of the sun disc (default 2e4, about 1e4 x the sky)",
      [&](const std::string& v) { options.sunRadiance = parseDouble("--sun-radiance", v, 0, 1e12); });
  if (parser.parseOrShowHelp(args)) return 0;
  checkImagePath("--out", out, true);
  const EnvImage sky = makeProceduralSky(options);
  writeExr(out, sky.width, sky.height, sky.rgb);
  const float peak = *std::max_element(sky.rgb.begin(), sky.rgb.end());
  std::printf("wrote %s (%dx%d, peak radiance %.4g)\n", out.c_str(), sky.width, sky.height, peak);
  return 0;
}

}  // namespace iblx::cli
