#pragma once

// Scans of synthetic 2D fans, their points in acquisition order and no lines yet (a loader's
// reconstructScanLines() finds them; oneLinePer() gives them without a turntable angle).

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

#include "clearway/scan.h"

namespace clearway::test {

inline constexpr double kFanDeg = std::numbers::pi / 180.0;

inline void addDirection(Scan& scan, const Eigen::Vector3d& direction, double range) {
  const Eigen::Vector3d p = range * direction;
  scan.points.push_back({float(p.x()), float(p.y()), float(p.z())});
  scan.status.push_back(PointStatus::kValid);
}

// Vertical half lines like the PCL room scan: elevation sweeps +80 -> -80 deg at a fixed azimuth,
// 2 deg from one fan to the next.
inline Scan verticalFans(int fans, int points_per_fan) {
  Scan scan;
  for (int f = 0; f < fans; ++f) {
    const double azimuth = f * 2.0 * kFanDeg;
    for (int k = 0; k < points_per_fan; ++k) {
      const double elevation = (80.0 - 160.0 * k / (points_per_fan - 1)) * kFanDeg;
      addDirection(scan,
                   {std::cos(elevation) * std::cos(azimuth),
                    std::cos(elevation) * std::sin(azimuth), std::sin(elevation)},
                   3.0 + 0.5 * std::sin(k * 0.1));
    }
  }
  return scan;
}

// Horizontal fans like the octomap scan: azimuth sweeps -90 -> +90 deg, tilted down line by line.
inline Scan horizontalFans(int fans, int points_per_fan) {
  Scan scan;
  for (int f = 0; f < fans; ++f) {
    const double tilt = (20.0 - f * 0.5) * kFanDeg;
    for (int k = 0; k < points_per_fan; ++k) {
      const double azimuth = (-90.0 + 180.0 * k / (points_per_fan - 1)) * kFanDeg;
      addDirection(
          scan,
          {std::cos(tilt) * std::cos(azimuth), std::cos(tilt) * std::sin(azimuth), std::sin(tilt)},
          5.0);
    }
  }
  return scan;
}

// A nodding scanner's fans (3DTK's walkway scan): each a half plane holding the sideways axis,
// swept in 1 deg steps from one side through forward to the other (181 returns), tilted `step_deg`
// more than the one before from -40 deg on.
inline Scan noddingFans(int fans, double step_deg) {
  Scan scan;
  for (int f = 0; f < fans; ++f) {
    const double tilt = (-40.0 + f * step_deg) * kFanDeg;
    for (int k = 0; k <= 180; ++k) {
      const double across = (-90.0 + k) * kFanDeg;
      addDirection(
          scan,
          {std::cos(across) * std::cos(tilt), std::sin(across), std::cos(across) * std::sin(tilt)},
          4.0 + 0.5 * std::sin(0.1 * k + f));
    }
  }
  return scan;
}

// The scan's points as lines of `per_line` returns each, without a turntable angle.
inline void oneLinePer(Scan& scan, std::size_t per_line) {
  scan.lines.clear();
  for (std::size_t first = 0; first < scan.size(); first += per_line)
    scan.lines.push_back(
        {first, std::min(per_line, scan.size() - first), std::numeric_limits<double>::quiet_NaN()});
}

}  // namespace clearway::test
