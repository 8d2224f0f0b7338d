#pragma once

// The simulated RoSi: a SICK LMS200 half line (180 beams, alpha = 0 .. 89.5 deg) turned by the
// turntable through one revolution, observing a scene, with per-point ground truth.
// Scanner frame (paper eq. 1-3): x = cos b cos a d, y = sin b cos a d, z = sin a d; z = turntable
// axis.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "clearway/point_class.h"
#include "clearway/progress.h"
#include "clearway/scan.h"
#include "clearway/sim/scene.h"

namespace clearway::sim {

struct SensorModel {
  int lines = 200;            // lines per revolution (LMS200: 37.5 lines/s)
  int points_per_line = 180;  // a half line at 0.5 deg
  double alpha_step_deg = 0.5;
  double range_noise_sigma = 0.01;  // [m]
  double max_range = 30.0;          // beyond it: no return [m]
  bool mixed_pixels = false;        // average ranges across depth edges, as real beams do
  // Share of the returns lost at random, as dark or wet surfaces, puddles and dust lose them: no
  // return (drawn from a generator of its own, so the rest of the scan is the same).
  double dropout = 0.0;
  std::uint32_t seed = 1;

  static constexpr double kLineRateHz = 37.5;
  // Lines per revolution at a turntable speed [deg/s].
  static int linesForSpeed(double degrees_per_second);
};

// Where the scanner is and where its turntable axis points, in the scene's world frame.
struct ScannerPlacement {
  Eigen::Vector3d position{0.0, 0.0, 1.0};
  Eigen::Vector3d axis{1.0, 0.0, 0.0};
  double axis_roll_deg = 0.0;  // turns the beta = 0 direction about the axis

  Eigen::Isometry3d worldFromScanner() const;
};
ScannerPlacement defaultPlacement(const Scene& scene);

// How far from the scene's origin the scanner may stand, per coordinate [m]: as far as any scanner
// measures (a pose sidecar's translation is held to the same).
inline constexpr double kFarthestScannerPosition = 10'000.0;

// "[x, y, z]" as the scene and truth files' errors quote a vector (readableNumber each).
std::string vectorText(const Eigen::Vector3d& v);

// Why `placement` is no scanner's place, naming its keys after `prefix` ("scanner." gives
// "scanner.position = [0, 0, 1e+308] lies more than 10 km from the origin"): a position that is
// not finite or more than kFarthestScannerPosition out, an axis that is zero or not finite, an
// axis roll outside -360 .. 360 deg. Empty when it is a place.
std::string placementProblem(const ScannerPlacement& placement, const std::string& prefix);

// One planar (or curved) surface of the scene that the scan saw.
struct SurfaceTruth {
  int id = -1;
  std::string primitive;
  int face = -1;
  PointClass point_class = PointClass::kNone;
  bool planar = true;
  // Plane n . p = offset in the scanner frame (n unit, pointing towards the scanner side).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;
  std::size_t points = 0;
};

struct GroundTruth {
  std::string scan;  // the scan's file name, as the truth file gives it (empty: not said)
  Scene scene;
  SensorModel sensor;
  ScannerPlacement placement;
  std::vector<PointClass> classes;     // per scan point; kNone for no return
  std::vector<std::int32_t> surfaces;  // per scan point; -1 for no return
  std::vector<SurfaceTruth> seen_surfaces;
};

struct SimulatedScan {
  Scan scan;
  GroundTruth truth;
};

// Surface ids are primitive * 8 + face.
inline int surfaceId(int primitive, int face) {
  return primitive * 8 + face;
}

// Throws std::invalid_argument for a placement that is no place (placementProblem) or inside one
// of the scene's solids.
SimulatedScan simulateRosi(const Scene& scene, const SensorModel& sensor,
                           const ScannerPlacement& placement,
                           const ProgressCallback& progress = {});

class RayCaster;

// One half line at turntable angle `beta` [rad]: the range of each of the sensor's beams
// (alpha = k * alpha_step), NaN for no return, with range noise drawn from `seed`. The emulator
// serves these line by line, as the LMS200 measures them.
std::vector<double> simulateLineRanges(const Scene& scene, const RayCaster& caster,
                                       const SensorModel& sensor, const ScannerPlacement& placement,
                                       double beta, std::uint32_t seed);

}  // namespace clearway::sim
