#include "pcd_writer.h"

#include <pcl/io/lzf.h>

#include <charconv>
#include <cstring>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"

namespace clearway::pcd {
namespace {

// Shortest text that reads back as the same float (or double), "nan" for no return: what PCL's
// reader and ours parse.
template <typename T>
void appendNumber(std::string& out, T value) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  out.append(text, error == std::errc() ? end : text);
}

std::string headerText(const FloatCloud& cloud, const char* data) {
  std::string fields, sizes, types, counts;
  for (const std::string& name : cloud.field_names) {
    fields += " " + name;
    sizes += " 4";
    types += " F";
    counts += " 1";
  }
  std::string header = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS" + fields +
                       "\nSIZE" + sizes + "\nTYPE" + types + "\nCOUNT" + counts + "\nWIDTH " +
                       std::to_string(cloud.width) + "\nHEIGHT " + std::to_string(cloud.height) +
                       "\nVIEWPOINT";
  for (const double value : cloud.viewpoint) {
    header += ' ';
    appendNumber(header, value);
  }
  header += "\nPOINTS " + std::to_string(std::uint64_t(cloud.width) * cloud.height) + "\nDATA " +
            data + "\n";
  return header;
}

void writeAscii(CheckedFile& file, const FloatCloud& cloud) {
  const std::size_t fields = cloud.field_names.size();
  std::string line;
  for (std::size_t start = 0; start < cloud.values.size(); start += fields) {
    line.clear();
    for (std::size_t f = 0; f < fields; ++f) {
      if (f > 0) line += ' ';
      const float value = cloud.values[start + f];
      if (value != value)
        line += "nan";
      else
        appendNumber(line, value);
    }
    line += '\n';
    file.write(line);
  }
}

// binary_compressed as PCL defines it: the fields one after another (all x, then all y, ...),
// LZF-compressed, preceded by the compressed and the uncompressed size as little-endian uint32.
void writeCompressed(CheckedFile& file, const FloatCloud& cloud,
                     const std::filesystem::path& target) {
  const std::size_t fields = cloud.field_names.size();
  const std::size_t points = fields ? cloud.values.size() / fields : 0;
  std::vector<float> by_field(cloud.values.size());
  for (std::size_t f = 0; f < fields; ++f)
    for (std::size_t i = 0; i < points; ++i)
      by_field[f * points + i] = cloud.values[i * fields + f];
  const std::size_t raw_bytes = by_field.size() * sizeof(float);
  if (raw_bytes > 0xFFFFFFFFULL / 2)
    throw ScanError(target, "cannot write: the cloud is too large for binary_compressed PCD");
  // LZF never grows data by more than about 1/32; the margin covers that and tiny inputs.
  std::string packed(raw_bytes + raw_bytes / 16 + 64, '\0');
  std::uint32_t sizes[2] = {0, std::uint32_t(raw_bytes)};
  if (raw_bytes > 0) {
    sizes[0] = pcl::lzfCompress(by_field.data(), std::uint32_t(raw_bytes), packed.data(),
                                std::uint32_t(packed.size()));
    if (sizes[0] == 0) throw ScanError(target, "cannot write: LZF compression failed");
  }
  file.write(std::string_view(reinterpret_cast<const char*>(sizes), sizeof sizes));
  file.write(std::string_view(packed.data(), sizes[0]));
}

}  // namespace

void writeFloatCloud(const std::filesystem::path& path, const std::filesystem::path& target,
                     const FloatCloud& cloud, PcdEncoding encoding) {
  static constexpr const char* kDataNames[] = {"ascii", "binary", "binary_compressed"};
  CheckedFile file(path, target);
  file.write(headerText(cloud, kDataNames[int(encoding)]));
  switch (encoding) {
    case PcdEncoding::kAscii:
      writeAscii(file, cloud);
      break;
    case PcdEncoding::kBinary:
      file.write(std::string_view(reinterpret_cast<const char*>(cloud.values.data()),
                                  cloud.values.size() * sizeof(float)));
      break;
    case PcdEncoding::kBinaryCompressed:
      writeCompressed(file, cloud, target);
      break;
  }
  file.close();
}

}  // namespace clearway::pcd
