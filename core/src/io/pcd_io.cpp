// PCD through PCL's reader and writer. Our own header check (pcd_header.cpp) runs first so that
// PCL never allocates for an absurd or truncated file.

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <limits>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_lines.h"
#include "pcd_ascii_body.h"
#include "pcd_header.h"
#include "pcd_writer.h"
#include "readers.h"

namespace clearway {
namespace detail {
namespace {

// Reads element `element` of a field at `offset` of a point record, converted to float.
float readAsFloat(const std::uint8_t* record, const pcl::PCLPointField& field, int element) {
  const std::uint8_t* at =
      record + field.offset + std::size_t(element) * pcl::getFieldSize(field.datatype);
  auto load = [at]<typename T>(T) {
    T value;
    std::memcpy(&value, at, sizeof(T));
    return static_cast<float>(value);
  };
  switch (field.datatype) {
    case pcl::PCLPointField::FLOAT32:
      return load(float{});
    case pcl::PCLPointField::FLOAT64:
      return load(double{});
    case pcl::PCLPointField::INT8:
      return load(std::int8_t{});
    case pcl::PCLPointField::UINT8:
      return load(std::uint8_t{});
    case pcl::PCLPointField::INT16:
      return load(std::int16_t{});
    case pcl::PCLPointField::UINT16:
      return load(std::uint16_t{});
    case pcl::PCLPointField::INT32:
      return load(std::int32_t{});
    case pcl::PCLPointField::UINT32:
      return load(std::uint32_t{});
    case pcl::PCLPointField::INT64:
      return load(std::int64_t{});
    case pcl::PCLPointField::UINT64:
      return load(std::uint64_t{});
    default:
      return std::numeric_limits<float>::quiet_NaN();
  }
}

const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& cloud,
                                    std::initializer_list<const char*> names) {
  for (const char* name : names)
    for (const pcl::PCLPointField& field : cloud.fields)
      if (field.name == name) return &field;
  return nullptr;
}

SensorPose poseFromViewpoint(const std::array<double, 7>& viewpoint) {
  const double w = viewpoint[3], x = viewpoint[4], y = viewpoint[5], z = viewpoint[6];
  SensorPose pose;
  pose.position = {viewpoint[0], viewpoint[1], viewpoint[2]};
  pose.rotation = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                   2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
  return pose;
}

}  // namespace

Scan readPcd(const std::filesystem::path& file, const LoadOptions& options) {
  std::uintmax_t file_size = 0;
  const std::string prefix = readFilePrefix(file, pcd::kHeaderPrefixBytes, file_size);
  const pcd::Header header = pcd::parseHeader(file, prefix, file_size, options.max_points);
  refuseBeyondMemory(file, header.points, file_size, options);
  if (header.encoding == pcd::Encoding::kAscii) pcd::checkAsciiBody(file, header);
  reportProgress(options.progress, 0.05);

  // PCL reports its own failures on stderr; ours are clearer and go through ScanError.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int pcd_version = 0;
  pcl::PCDReader reader;
  int read_result = 0;
  try {
    read_result = reader.read(file.string(), cloud, origin, orientation, pcd_version);
  } catch (const std::exception& error) {
    // PCL throws where our check and its own header parse disagree (a body line it takes for a
    // header keyword: std::length_error from a string it sizes by it).
    throw ScanError(file, std::string("PCD body is corrupt: ") + error.what());
  }
  if (read_result < 0) throw ScanError(file, "PCD body is corrupt or shorter than its header says");
  const std::size_t count = std::size_t(cloud.width) * cloud.height;
  if (count != header.points || cloud.data.size() < count * cloud.point_step)
    throw ScanError(file, "PCD body holds fewer points than its header says");
  reportProgress(options.progress, 0.5);

  // PCL parses the header again, its own way: a body line that starts with one of its keywords
  // (a v0.5 "COLUMNS" inside ascii data) replaces the fields our check saw. Every field read below
  // must be there and lie within a record.
  auto within = [&](const pcl::PCLPointField* field) {
    return !field || (pcl::getFieldSize(field->datatype) > 0 &&
                      std::size_t(field->offset) + pcl::getFieldSize(field->datatype) <=
                          std::size_t(cloud.point_step));
  };
  const pcl::PCLPointField* x = findField(cloud, {"x"});
  const pcl::PCLPointField* y = findField(cloud, {"y"});
  const pcl::PCLPointField* z = findField(cloud, {"z"});
  if (!x || !y || !z)
    throw ScanError(file, "PCD body does not read as the header says: no x, y and z fields");
  const pcl::PCLPointField* intensity =
      findField(cloud, {"intensity", "remission", "reflectance", "i"});
  const pcl::PCLPointField* alpha = findField(cloud, {"alpha"});
  const pcl::PCLPointField* beta = findField(cloud, {"beta"});
  const pcl::PCLPointField* ring = nullptr;
  for (const char* name : kRingFieldNames)
    if (!ring) ring = findField(cloud, {name});
  for (const pcl::PCLPointField* field : {x, y, z, intensity, alpha, beta, ring})
    if (!within(field))
      throw ScanError(file, "PCD field '" + field->name + "' lies outside its point record");

  Scan scan;
  scan.points.reserve(count);
  scan.status.reserve(count);
  if (intensity) scan.intensity.resize(count);
  if (alpha) scan.alpha.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* record = cloud.data.data() + i * cloud.point_step;
    appendPoint(scan, readAsFloat(record, *x, 0), readAsFloat(record, *y, 0),
                readAsFloat(record, *z, 0));
    if (intensity) scan.intensity[i] = readAsFloat(record, *intensity, 0);
    if (alpha) scan.alpha[i] = readAsFloat(record, *alpha, 0);
  }

  // Multi-beam drivers (Velodyne, Ouster) tag each point with its beam: one line per ring.
  if (ring && cloud.height <= 1) {
    std::vector<double> ring_numbers(count);
    for (std::size_t i = 0; i < count; ++i)
      ring_numbers[i] = readAsFloat(cloud.data.data() + i * cloud.point_step, *ring, 0);
    if (const std::string why_not = groupIntoRings(scan, ring_numbers); !why_not.empty())
      throw ScanError(file, "PCD field '" + ring->name + "': " + why_not);
  }
  if (cloud.height > 1) {
    // Organised: one row per scan line, as the RoSi writes it.
    for (std::size_t row = 0; row < cloud.height; ++row) {
      ScanLine line{row * cloud.width, cloud.width};
      for (std::size_t i = line.first; beta && i < line.first + line.count; ++i) {
        const float value = readAsFloat(cloud.data.data() + i * cloud.point_step, *beta, 0);
        if (std::isfinite(value)) {
          line.beta = value;
          break;
        }
      }
      scan.lines.push_back(line);
    }
  }
  if (header.viewpoint != std::array<double, 7>{0, 0, 0, 1, 0, 0, 0})
    scan.sensor_pose = poseFromViewpoint(header.viewpoint);

  static constexpr const char* kEncodingNames[] = {"ascii", "binary", "binary_compressed"};
  scan.metadata.format = std::string("pcd (") + kEncodingNames[int(header.encoding)] + ")";
  scan.metadata.frame = "as stored: metres, right-handed";
  return scan;
}

}  // namespace detail

void saveRosiPcd(const Scan& scan, const std::filesystem::path& file, PcdEncoding encoding) {
  const bool organised = scan.isOrganised();
  pcd::FloatCloud cloud;
  cloud.field_names = {"x", "y", "z", "intensity", "alpha", "beta", "range"};
  const std::size_t fields = cloud.field_names.size();
  cloud.width = static_cast<std::uint32_t>(organised ? scan.pointsPerLine() : scan.size());
  cloud.height = static_cast<std::uint32_t>(organised ? scan.lines.size() : 1);
  cloud.values.resize(std::size_t(cloud.width) * cloud.height * fields);

  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t line_index = 0; line_index < scan.lines.size(); ++line_index) {
    const ScanLine& line = scan.lines[line_index];
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      const Point3f& p = scan.points[i];
      // Only true no-returns become NaN: self hits and saturated ranges keep their coordinates so
      // nothing the scanner measured is lost; the loader marks them again.
      const bool no_return = scan.status[i] == PointStatus::kNoReturn;
      const float range = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
      const float record[] = {no_return ? kNaN : p.x,
                              no_return ? kNaN : p.y,
                              no_return ? kNaN : p.z,
                              scan.intensity.empty() ? 0.0F : scan.intensity[i],
                              scan.alpha.empty() ? kNaN : scan.alpha[i],
                              static_cast<float>(line.beta),
                              no_return ? kNaN : range};
      std::memcpy(cloud.values.data() + i * fields, record, sizeof record);
    }
  }

  if (scan.sensor_pose) {
    const auto& pose = *scan.sensor_pose;
    Eigen::Matrix3d rotation;
    rotation << pose.rotation[0], pose.rotation[1], pose.rotation[2], pose.rotation[3],
        pose.rotation[4], pose.rotation[5], pose.rotation[6], pose.rotation[7], pose.rotation[8];
    const Eigen::Quaterniond orientation(rotation);
    cloud.viewpoint = {pose.position[0], pose.position[1], pose.position[2], orientation.w(),
                       orientation.x(),  orientation.y(),  orientation.z()};
  }

  // Our own buffered, checked writer: PCL's memory-maps the file and a full disk kills the
  // process with SIGBUS before any error can be reported.
  writeFileAtomically(file, [&](const std::filesystem::path& temporary) {
    pcd::writeFloatCloud(temporary, file, cloud, encoding);
  });
}

}  // namespace clearway
