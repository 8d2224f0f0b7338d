#pragma once

// One reader per format; loadScan() picks one by extension and finishes the scan (self hits,
// line reconstruction, invariants). Readers fill points/status/intensity/alpha, and lines only when
// the file itself knows them.

#include <filesystem>
#include <string>

#include "clearway/io/scan_io.h"

namespace clearway::detail {

Scan readPcd(const std::filesystem::path& file, const LoadOptions& options);
Scan readPly(const std::filesystem::path& file, const LoadOptions& options);
Scan readXyz(const std::filesystem::path& file, const LoadOptions& options);
Scan readKittiBin(const std::filesystem::path& file, const LoadOptions& options);
Scan readUos(const std::filesystem::path& file, const LoadOptions& options);

// Reads at most `max_bytes` from the start of a file (for headers) and reports the file's size.
std::string readFilePrefix(const std::filesystem::path& file, std::size_t max_bytes,
                           std::uintmax_t& file_size);

// Checks the first bytes of a text scan (no binary data, a size within the limit, rows of at least
// three numbers after at most one header row) before the whole file is read; returns those rows.
// Throws ScanError naming what is wrong.
std::size_t checkTextScanStart(const std::filesystem::path& file);

// A real scan holds no point its sensor cannot have measured, or hardly any (corrupt records); a
// file with a larger share of them is not a scan.
constexpr double kMostImplausiblePointShare = 0.01;

// What loading and segmenting a scan holds at most per point [bytes]: `clearway-cli segment`
// peaked at 238 MB resident on the simulator's 1M-point garage (the libraries' own 25 MB
// included), `info` at 182 MB.
constexpr std::uint64_t kBytesPerPointToSegment = 250;

// Refuses a scan of `points` points read from a file of `file_bytes` when loading and segmenting
// it would take more than options.memory_budget (or the memory available now), naming both.
void refuseBeyondMemory(const std::filesystem::path& file, std::uint64_t points,
                        std::uint64_t file_bytes, const LoadOptions& options);

// Appends to what the user must know to read the result (ScanMetadata::caution).
void addCaution(Scan& scan, const std::string& caution);

// Adds a point, marking it kNoReturn when a coordinate is not finite.
void appendPoint(Scan& scan, float x, float y, float z);

}  // namespace clearway::detail
