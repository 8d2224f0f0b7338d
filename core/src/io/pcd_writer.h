#pragma once

// Writing a PCD through our own checked, buffered I/O (CheckedFile) instead of PCL's writer, which
// memory-maps the output and dies of SIGBUS when the disk is full.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "clearway/io/scan_io.h"

namespace clearway::pcd {

// A cloud of float32 fields, one record of `field_names.size()` floats per point, row by row.
struct FloatCloud {
  std::vector<std::string> field_names;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::array<double, 7> viewpoint{0, 0, 0, 1, 0, 0, 0};  // tx ty tz qw qx qy qz
  std::vector<float> values;                             // width * height * fields
};

// Writes `cloud` to `path` in `encoding`; errors name `target` (the file the user asked for).
void writeFloatCloud(const std::filesystem::path& path, const std::filesystem::path& target,
                     const FloatCloud& cloud, PcdEncoding encoding);

}  // namespace clearway::pcd
