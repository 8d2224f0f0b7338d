// Our PCD header check on arbitrary bytes: it must accept or refuse with ScanError, never crash,
// and what it accepts must be self-consistent.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "clearway/io/scan_error.h"
#include "io/pcd_header.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  // Claim a file size from the input too, so the size checks see large and small files.
  const std::uint64_t file_size = size + (size > 0 ? std::uint64_t(data[0]) << 20 : 0);
  try {
    const clearway::pcd::Header header =
        clearway::pcd::parseHeader("fuzz.pcd", bytes, file_size, 200'000'000);
    if (header.points != header.width * header.height || header.data_offset > size) std::abort();
  } catch (const clearway::ScanError&) {
  }
  return 0;
}
