// Camera checks (engine/geometry/camera.h).
#include "engine/geometry/camera.h"

#include "engine/core/setting.h"

#include <cmath>
#include <sstream>

namespace iblx {

void checkCamera(const CameraSpec& camera) {
  if (!std::isfinite(camera.azimuthDeg) || !(std::abs(camera.elevationDeg) <= 90.0)) {
    std::ostringstream s;
    s << " " << camera.azimuthDeg << "," << camera.elevationDeg
      << ": the azimuth must be finite and the elevation in [-90, 90] degrees";
    throw SettingError(Setting::Orbit, "", s.str());
  }
  if (!(camera.zoom > 0.0) || !std::isfinite(camera.zoom)) {
    std::ostringstream s;
    s << " " << camera.zoom << ": must be a finite number > 0";
    throw SettingError(Setting::Zoom, "", s.str());
  }
}

}  // namespace iblx
