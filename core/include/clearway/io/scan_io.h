#pragma once

// Reading every scan format Clearway meets into one Scan, and writing the RoSi's native PCD.
// See docs/FORMATS.md for the formats and the axis conversions.

#include <cstdint>
#include <filesystem>
#include <string>

#include "clearway/io/scan_error.h"
#include "clearway/progress.h"
#include "clearway/scan.h"

namespace clearway {

enum class ScanFormat { kPcd, kPly, kXyz, kKittiBin, kUos };

struct LoadOptions {
  // Returns closer than this to the sensor are the robot or the mount: marked kSelfHit [m].
  double self_hit_radius = 0.3;
  // In files without a line structure, a new scan line starts where the angle along the line
  // jumps back by more than this [deg].
  double line_break_deg = 20.0;
  // Multi-beam frames: how many rings (beams) the sensor has; 0 = read the rings from the file
  // (a PCD `ring` field, organised rows, or the azimuth wrap). When the lines found do not number
  // this many, the rings are recovered from the elevation angles instead.
  std::size_t rings = 0;
  // Files claiming more points than this are refused before anything is allocated.
  std::uint64_t max_points = 200'000'000;
  // Memory the scan may take to load and segment [bytes]; 0: what the machine has available when
  // it is loaded (MemAvailable; unchecked where that cannot be read). A file claiming more points
  // than that holds is refused before anything is allocated, rather than the process killed by
  // the kernel part-way (the console with it).
  std::uint64_t memory_budget = 0;
  ProgressCallback progress;
};

// The format an extension names; throws ScanError for an unknown extension.
ScanFormat formatFromPath(const std::filesystem::path& file);
std::string formatName(ScanFormat format);

// Whether a file found in a folder of scans is one: a known extension and, for the text formats
// (whose .txt they share with README and SOURCE notes), first lines that are rows of at least three
// numbers. For offering the files of a folder; loadScan says whether a scan is readable.
bool looksLikeScanFile(const std::filesystem::path& file);

// Loads any supported scan. Throws ScanError with a one-line reason for anything that is not a
// readable scan (missing, truncated, corrupt, empty, absurd sizes), OperationCancelled on cancel.
Scan loadScan(const std::filesystem::path& file, const LoadOptions& options = {});

enum class PcdEncoding { kAscii, kBinary, kBinaryCompressed };

// Writes a scan as RoSi native PCD (FIELDS x y z intensity alpha beta range; organised scans as
// WIDTH = points per line, HEIGHT = lines; no returns as NaN). The file appears atomically: it is
// written beside the target and renamed over it. Throws ScanError on failure.
void saveRosiPcd(const Scan& scan, const std::filesystem::path& file,
                 PcdEncoding encoding = PcdEncoding::kBinaryCompressed);

}  // namespace clearway
