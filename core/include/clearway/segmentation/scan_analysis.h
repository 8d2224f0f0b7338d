#pragma once

// Stages 1-4 of the pipeline and everything the traversability check needs that does not depend on
// the robot's size: computed once per scan and reused when the operator changes the robot.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "clearway/progress.h"
#include "clearway/scan.h"
#include "clearway/segmentation/line_segments.h"
#include "clearway/segmentation/params.h"
#include "clearway/segmentation/planes.h"
#include "clearway/segmentation/stairs.h"
#include "clearway/sensor_geometry.h"

namespace clearway {

// A regular grid on the reference ground plane (map frame: x, y on the plane, z up its normal).
struct MapGrid {
  double resolution = 0.05;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // map x, y of the lower-left cell's corner
  int width = 0;
  int height = 0;

  std::size_t cells() const { return std::size_t(width) * std::size_t(height); }
  std::size_t index(int column, int row) const {
    return std::size_t(row) * std::size_t(width) + std::size_t(column);
  }
  bool inside(int column, int row) const {
    return column >= 0 && row >= 0 && column < width && row < height;
  }
  // Cell of a map position; may be outside.
  Eigen::Vector2i cellOf(double x, double y) const {
    return {int(std::floor((x - origin.x()) / resolution)),
            int(std::floor((y - origin.y()) / resolution))};
  }
  Eigen::Vector2d centre(int column, int row) const {
    return {origin.x() + (column + 0.5) * resolution, origin.y() + (row + 0.5) * resolution};
  }
};

// A point that is not ground, as the map sees it.
struct MapObstacle {
  std::uint32_t cell = 0;
  float x = 0.0F, y = 0.0F, z = 0.0F;  // map position [m]
  float height = 0.0F;                 // above the local ground [m]
};

// Across a rotating scanner's sweep, nothing between two neighbouring lines was seen: an obstacle
// one line hit may reach into that wedge towards the next line's beam (docs/ALGORITHM.md, "Where
// an obstacle ends between two lines"). Per obstacle and side (the line before, the line after):
// the neighbouring beam's point when it is an obstacle too (whether it blocks depends on the
// robot), else where that beam was at the obstacle's range and how much farther it went on.
struct SweepNeighbours {
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // Set on an entry that indexes `beams` (the neighbour is ground, or off the grid).
  static constexpr std::uint32_t kBeam = 0x80000000U;
  struct Beam {
    float x = 0.0F, y = 0.0F, z = 0.0F;  // map position at the obstacle's range [m]
    float beyond = 0.0F;                 // its return's range less the obstacle's [m]
  };
  std::vector<std::array<std::uint32_t, 2>> of_obstacle;  // index into obstacles, kBeam | i, kNone
  std::vector<Beam> beams;
};

// Where a beam went down through the ground's level where no floor was seen: no floor there.
struct FloorCrossing {
  std::uint32_t cell = 0;
  float x = 0.0F, y = 0.0F;  // map position [m]
};
// Where two ground planes meet on the map, and the smallest step between them there.
struct GroundContact {
  int a = -1, b = -1;
  float step = 0.0F;
};

// The ground triangles between neighbouring scan lines as a mesh: each corner point once, with the
// grid cell it lies in, and the triangles as indices into those corners. The 3D view colours it by
// the robot's map without mapping a point again.
struct GroundMesh {
  static constexpr std::uint32_t kOutsideGrid = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> points;  // per vertex: its scan point
  std::vector<std::uint32_t> cells;   // per vertex: its grid index, or kOutsideGrid
  std::vector<std::array<std::uint32_t, 3>> triangles;  // vertex indices
};

// A plane's map height h = c0 + c1 x + c2 y above the map point (x, y), from its coefficients
// (c0, c1, c2) (ScanAnalysis::height_coefficients).
inline double heightOnPlane(const Eigen::Vector3d& c, double x, double y) {
  return c[0] + c[1] * x + c[2] * y;
}

// Ground heights that rise by more than the robot's step over a run this long [m] are a step,
// however the ground triangles spread it (they join the last return below a step to the first
// above, a few centimetres apart): the cells' step rule compares heights over such runs, and a
// longer triangle keeps the step its corners span (MapInputs::seam_step).
inline constexpr double kStepRunLength = 0.15;

// How high the scanner looked about itself (map frame): per azimuth sector and per horizontal
// reach, the steepest rise (tan of the elevation) of a beam in that sector that went at least
// that far. A beam that came back went as far as its return; one that did not (no echo, out of
// range) went on. A cell's band between the ground and the robot's height was in view only where
// such a beam rises at least to its top over the cell (docs/ALGORITHM.md, "Above the scanner's
// view"): a RoSi whose turntable axis points down sees nothing above its own height, and an
// overhang there is never measured.
struct ViewLimit {
  static constexpr int kAzimuthSectors = 360;
  static constexpr double kReachStep = 0.5;  // [m]
  static constexpr int kReachClasses = 161;  // 0 .. 80 m; the last class: that far or farther
  // [sector * kReachClasses + reach class]; -infinity where no beam went that far.
  std::vector<float> rise;

  bool known() const { return !rise.empty(); }
  // The steepest rise of the beams about `azimuth` [rad] that went `distance` [m] or farther.
  float riseAt(double azimuth, double distance) const;
  static int sectorOf(double azimuth);
  // The reach class whose beams all went `distance` [m] or farther.
  static int reachClassAt(double distance);
};

struct MapInputs {
  MapGrid grid;
  std::vector<std::int16_t> ground_plane;  // per cell: index into planes, or -1
  // Per cell: the local ground's map z, the lowest of the cell's ground points or the ground
  // triangle's over its centre (not its plane's: an outdoor plane only approximates the ground).
  std::vector<float> ground_height;
  // Per cell: the step [m] the cell stands for between two ground levels, 0 elsewhere: the one a
  // ground triangle joining two planes (a low kerb seen from above, its face unseen) or reaching
  // ground no plane took in spans over it, where cells of two planes meet more than 5 cm apart at
  // least the planes' difference there, and the drop a long triangle of one plane bridges away
  // from the scanner (EdgeLimit::spannedStep). The traversability check blocks the cell for a
  // robot whose step is smaller.
  std::vector<float> seam_step;
  // Per ground cell: the widest obstacle that could stand between the sensor's samples there
  // unseen (hiddenObstacleSize(), sensor_geometry.h) [m]. The density check compares it with the
  // robot's step (docs/ALGORITHM.md, "Sparse scans never lie").
  std::vector<float> ground_spacing;
  // Where beams went down through the reference ground's level over unobserved cells: lost ones
  // (nothing stood there to send them back) and ones returned from well under it
  // (floor_crossings.h).
  std::vector<FloorCrossing> floor_crossings;
  std::vector<MapObstacle> obstacles;
  SweepNeighbours sweep_neighbours;  // empty for multi-beam frames
  std::vector<GroundContact> contacts;
  GroundMesh ground_mesh;
  ViewLimit view;
};

struct StageTiming {
  std::string stage;
  double milliseconds = 0.0;
};

struct ScanAnalysis {
  std::size_t scan_points = 0;
  std::size_t valid_points = 0;
  SensorGeometry sensor;  // kind, angular steps, whether the lines close a full turn
  std::vector<LineSegment> segments;
  std::size_t candidate_planes = 0;
  ValidatedPlanes planes;                         // kinds are set: ground / wall / ceiling / other
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // gravity's up in the scanner frame
  // Where `up` came from: the scan's pose (file, sidecar, operator) or the pipeline's estimate.
  PoseSource pose_source = PoseSource::kNone;
  double up_confidence = 1.0;  // 1 for a given pose, the estimate's confidence, 0 with neither
  // The robot's frame seen from the scanner, when acquisition recorded it (a pose sidecar: the
  // arm's kinematics give robot_from_scanner, the robot's frame standing on its floor).
  std::optional<Eigen::Isometry3d> robot_from_scanner;
  bool ground_found = false;
  std::string reason;  // why the result cannot be trusted, when it cannot
  int reference_ground = -1;
  std::vector<int> ground_planes;  // ground candidates, reference first
  Eigen::Isometry3d map_from_scanner = Eigen::Isometry3d::Identity();
  MapInputs inputs;
  StairDetection stairs;  // staircases and, per cell of inputs.grid, which one covers it
  std::vector<StageTiming> timings;

  // Map height of a ground plane above the map point (x, y).
  double planeHeight(int plane, double x, double y) const {
    return heightOnPlane(height_coefficients[std::size_t(plane)], x, y);
  }
  std::vector<Eigen::Vector3d> height_coefficients;  // per plane, set with the map frame
};

// Runs stages 1-4 and prepares the map inputs. Throws OperationCancelled when asked to stop.
ScanAnalysis analyseScan(const Scan& scan, const SegmentationParams& params, int threads = 2,
                         const ProgressCallback& progress = {});

// The up direction a scan's pose gives (world z seen from the scanner); the file's own z axis
// when it has none (the analysis then estimates it instead: see up_estimation.h).
Eigen::Vector3d upDirection(const Scan& scan);

// Why no ground was found, from what the stages saw (one line, a floor that failed validation,
// no plane, only ceilings, only walls): the cause, then what to do. `up_known`: analysis.up is
// the pose's or a trusted estimate (which planes are floors can be told).
std::string noGroundReason(const ScanAnalysis& analysis, const GroundParams& params,
                           bool up_known = true);

// Internal steps, exposed for tests.
void selectGround(ScanAnalysis& analysis, const GroundParams& params);
// Multi-beam frames: a ground plane whose own points lie mostly on the reference ground (within its
// support band and area) is a patch of that ground fitted from a few rings, tilted by their noise:
// its points on the reference go to the reference, the rest (where the tilt carried it into cars
// and kerbs) to no plane, and it stops being ground. Returns how many planes were absorbed.
std::size_t absorbGroundPatches(const Scan& scan, const ValidationParams& validation,
                                const SensorSpread& spread, ScanAnalysis& analysis);
// Multi-beam frames: ground is what the robot can drive onto from the reference ground, over a step
// no higher than `max_rise` (its step) along a seam at least `min_width` long (its width): a ground
// plane is kept when its own points within max_rise of a kept plane, over that plane's area, run
// that far along its rings. The others (car roofs and bonnets, flat and below the sensor, or tilted
// planes touching the road at a point) stop being ground, their points on no plane. Returns how
// many planes were dropped.
std::size_t dropUnreachableGround(const Scan& scan, double max_rise, double min_width,
                                  ScanAnalysis& analysis);
// Ground is the lowest surface in its column (any sensor). A ground return with a return lower by
// more than a step (and a drivable slope's rise) in its column goes to no plane; a ground plane
// other than the reference most of whose returns are such is a plane fitted along a face (a
// hedge, a wall's foot) or over one (its top, a table): it stops being ground. Returns how many
// planes were dropped.
std::size_t dropGroundOverLowerReturns(const Scan& scan, double max_rise, double max_slope_deg,
                                       ScanAnalysis& analysis, int threads = 2);
// The robot-independent map inputs of an analysis whose ground is selected (stairs detected).
MapInputs prepareMapInputs(const Scan& scan, const SegmentationParams& params,
                           const ScanAnalysis& analysis, int threads = 2);

}  // namespace clearway
