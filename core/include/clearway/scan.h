#pragma once

// The scan model every stage of Clearway works on: points grouped into scan lines in acquisition
// order, because the segmentation fits line segments per scan line (paper, section II-A).

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace clearway {

struct Point3f {
  float x = 0.0F;
  float y = 0.0F;
  float z = 0.0F;
};

// One scan line: a contiguous run of Scan::points.
struct ScanLine {
  std::size_t first = 0;  // index of the line's first point
  std::size_t count = 0;  // number of points, invalid ones included
  // Turntable angle beta of the line [rad]; NaN when the file does not give it.
  double beta = std::numeric_limits<double>::quiet_NaN();
};

// Where the sensor was, in the frame the file's poses use (right-handed, metres).
struct SensorPose {
  std::array<double, 3> position{0.0, 0.0, 0.0};
  std::array<double, 9> rotation{1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};  // row-major
};

// Precedence, highest first: what the operator said (command line or console), the sidecar
// SCAN.pose.json written by acquisition, the file itself (PCD VIEWPOINT, 3DTK .pose); with none
// of them the up direction is estimated from the scan (or refused, with --up none).
enum class PoseSource : std::uint8_t {
  kNone,         // nothing known; the pipeline estimates or refuses
  kFile,         // PCD VIEWPOINT, 3DTK .pose
  kSidecar,      // SCAN.pose.json beside the scan
  kCommandLine,  // --pose / --up (or the console's pose fields)
  kOperator,     // the console: the operator picked the floor or confirmed an estimate
  kEstimated,    // the pipeline's own estimate of the up direction (never set by resolution)
};

// Why a point carries no usable measurement.
enum class PointStatus : std::uint8_t {
  kValid = 0,
  kNoReturn = 1,  // NaN/absent coordinates (no echo, glass, out of range)
  kMaxRange = 2,  // saturated range the sensor reports instead of "no echo"
  kSelfHit = 3,   // closer than the self-hit radius: the robot or the scanner mount
};

struct ScanMetadata {
  std::string source_path;
  std::string format;  // e.g. "pcd (binary_compressed)", "3dtk uos"
  std::string frame;   // how the file's axes and units were mapped into Clearway's frame
  // What the loader could not work out and the user must know to read the result (empty: none),
  // e.g. a multi-beam frame whose rings it could not tell apart.
  std::string caution;
};

struct Scan {
  // Coordinates in Clearway's frame: right-handed, metres, z up where the format defines up. For
  // RoSi files this is the scanner frame with z the turntable axis. Points whose status is not
  // kValid may hold NaN or meaningless coordinates and must be skipped by every consumer.
  std::vector<Point3f> points;
  std::vector<PointStatus> status;        // one per point
  std::vector<float> intensity;           // remission per point; empty when the format has none
  std::vector<float> alpha;               // measurement angle per point [rad]; empty when unknown
  std::vector<ScanLine> lines;            // cover points exactly, in order
  std::optional<SensorPose> sensor_pose;  // world_from_scanner
  PoseSource pose_source = PoseSource::kNone;  // where sensor_pose came from (see pose.h)
  ScanMetadata metadata;

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  bool isValid(std::size_t index) const { return status[index] == PointStatus::kValid; }
  std::size_t validCount() const;
  // True when there is more than one line and every line has the same number of points.
  bool isOrganised() const;
  // Points per line when organised; otherwise the longest line.
  std::size_t pointsPerLine() const;
  std::span<const Point3f> linePoints(std::size_t line) const;
};

// Axis-aligned bounds of the valid points; empty() when there are none.
struct Bounds {
  Point3f min{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
              std::numeric_limits<float>::max()};
  Point3f max{std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(),
              std::numeric_limits<float>::lowest()};
  bool empty() const { return min.x > max.x; }
};
Bounds validBounds(const Scan& scan);

// Checks the invariants above (sizes agree, lines cover the points, invalid where non-finite) and
// throws std::logic_error naming the first broken one. Loaders call it before returning.
void checkScanInvariants(const Scan& scan);

// Marks valid points closer than `radius` metres to the origin as self hits; returns how many.
std::size_t markSelfHits(Scan& scan, double radius);

}  // namespace clearway
