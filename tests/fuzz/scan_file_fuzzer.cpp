// One scan reader on arbitrary bytes, through loadScan() as a user would: the bytes are written to
// a scratch file with the harness's extension (CLEARWAY_FUZZ_EXTENSION). The reader must load the
// scan or refuse it with ScanError; a crash, a sanitizer report or a memory blow-up is a finding.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "clearway/io/scan_io.h"

namespace {

std::filesystem::path scratchFile() {
  const std::filesystem::path folder =
      std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
  return folder / ("clearway-fuzz-" + std::to_string(::getpid()) + CLEARWAY_FUZZ_EXTENSION);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file = scratchFile();
  {
    std::ofstream stream(file, std::ios::binary | std::ios::trunc);
    stream.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  clearway::LoadOptions options;
  // Small enough that a header claiming the limit cannot exhaust the fuzzer's memory limit.
  options.max_points = 1'000'000;
  try {
    const clearway::Scan scan = clearway::loadScan(file, options);
    if (scan.points.size() != scan.status.size()) __builtin_trap();
  } catch (const clearway::ScanError&) {
  }
  return 0;
}
