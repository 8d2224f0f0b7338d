#pragma once

// Our own check of an ASCII PCD body before PCL reads it. PCL's reader is lenient: a row cut short
// (a file cut off mid-row), a word where a number belongs, or rows beyond POINTS were read as
// points or dropped without a word, and the scan looked whole.

#include <filesystem>

#include "pcd_header.h"

namespace clearway::pcd {

// Throws ScanError naming the first line that is not a row of the header's numbers (one per field
// element: the sum of COUNT), or how many rows the body holds where they are not POINTS. Blank
// lines are skipped, as PCL skips them.
void checkAsciiBody(const std::filesystem::path& file, const Header& header);

}  // namespace clearway::pcd
