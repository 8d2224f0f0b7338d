#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string_view>

#include "clearway/progress.h"

namespace clearway::detail {

// Parses whitespace- or comma-separated number rows (blank lines and '#' comments skipped).
// Every row needs at least `min_columns` numbers; up to four are passed to `row`, the rest ignored.
// A leading row that is not numeric is taken as a column header once. Throws ScanError naming the
// line of the first malformed row.
void parseNumberRows(const std::filesystem::path& file, std::string_view text,
                     std::size_t min_columns,
                     const std::function<void(const std::array<double, 4>&, std::size_t)>& row,
                     const ProgressCallback& progress);

}  // namespace clearway::detail
