#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string_view>

#include "clearway/progress.h"

namespace clearway::detail {

// The bytes a UTF-8 text may start with to say it is UTF-8; not part of the text.
inline constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

// One number as text writes it (decimal or exponent, nan, inf, an optional sign) filling all of
// `word`; one too large for a double is infinite, too small zero. False for anything else.
bool parseNumberWord(std::string_view word, double& value);

// What parseNumberRows expects of the rows.
struct NumberRowRules {
  std::size_t min_columns = 3;  // every row holds at least this many numbers
  // A leading row that is not numeric is a column header (an .xyz's "x y z"); a format whose
  // header says what follows (PLY) allows none.
  bool header_row_allowed = true;
  // Every row holds as many numbers as the first: a text scan's columns are the same all through
  // (rows of x y z after rows of x y z intensity lost the intensity, or the reverse gave it 0).
  // Off for a format that checks its own rows (PLY, whose faces follow the vertices).
  bool same_columns = true;
  std::size_t lines_before = 0;  // the file's lines before `text`, for the line numbers
};

// Parses whitespace- or comma-separated number rows (blank lines and '#' comments skipped; a UTF-8
// byte-order mark before the first is skipped too). Up to four numbers of a row are passed to
// `row` with the row's count, the rest ignored; a number too large for a double is infinite (not
// a point). Throws ScanError naming the line of the first malformed row (a word, too few numbers,
// or, with `same_columns`, another count than the first row's).
void parseNumberRows(const std::filesystem::path& file, std::string_view text,
                     const NumberRowRules& rules,
                     const std::function<void(const std::array<double, 4>&, std::size_t)>& row,
                     const ProgressCallback& progress);

}  // namespace clearway::detail
