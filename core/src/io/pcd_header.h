#pragma once

// Our own parse of a PCD header, done before PCL sees the file: PCL trusts WIDTH/HEIGHT/POINTS and
// the compressed sizes, so absurd or truncated files are refused here with a clear reason.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace clearway::pcd {

struct Field {
  std::string name;
  int size = 4;     // bytes per element
  char type = 'F';  // F float, I signed, U unsigned
  int count = 1;    // elements
};

enum class Encoding { kAscii, kBinary, kBinaryCompressed };

struct Header {
  std::vector<Field> fields;
  std::uint64_t width = 0;
  std::uint64_t height = 0;
  std::uint64_t points = 0;
  std::array<double, 7> viewpoint{0, 0, 0, 1, 0, 0, 0};  // tx ty tz qw qx qy qz
  Encoding encoding = Encoding::kAscii;
  std::size_t data_offset = 0;  // first byte after the DATA line

  std::size_t pointSize() const;
  int fieldIndex(std::string_view name) const;  // -1 when absent
};

// Parses the header from the file's first bytes and checks its sizes against the file's size;
// throws ScanError naming the problem. ASCII bodies are counted by the reader itself.
Header parseHeader(const std::filesystem::path& file, std::string_view prefix,
                   std::uint64_t file_size, std::uint64_t max_points);

// How many bytes of a file parseHeader needs to see at most.
constexpr std::size_t kHeaderPrefixBytes = 64 * 1024;

}  // namespace clearway::pcd
