#include "ascii_rows.h"

#include <algorithm>
#include <charconv>
#include <limits>
#include <string>

#include "clearway/io/scan_error.h"

namespace clearway::detail {
namespace {

bool isSeparator(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == '\r' || c == ';';
}

// Parses up to four numbers of one line; returns how many, or -1 for a non-numeric token.
int parseLine(std::string_view line, std::array<double, 4>& values) {
  int columns = 0;
  std::size_t at = 0;
  while (true) {
    while (at < line.size() && isSeparator(line[at]))
      ++at;
    if (at == line.size()) return columns;
    std::size_t end = at;
    while (end < line.size() && !isSeparator(line[end]))
      ++end;
    double value = 0.0;
    if (!parseNumberWord(line.substr(at, end - at), value)) return -1;
    if (columns < 4) values[std::size_t(columns)] = value;
    ++columns;
    at = end;
  }
}

// Whether a row writes its numbers with decimal commas ("1,48 0,00 0,06", "1,5;0,0;0,1"): words
// between spaces, tabs or semicolons that are each digits, one comma and digits, three or more of
// them. Read with the comma as a separator, such a row gave twice the numbers, x a whole number
// and the fractions as y, z and intensity, and loaded without a word.
bool writesDecimalCommas(std::string_view line) {
  std::size_t words = 0, at = 0;
  const auto between = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == ';'; };
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  while (true) {
    while (at < line.size() && between(line[at]))
      ++at;
    if (at == line.size()) return words >= 3;
    std::size_t end = at;
    while (end < line.size() && !between(line[end]))
      ++end;
    std::string_view word = line.substr(at, end - at);
    if (word.front() == '-' || word.front() == '+') word.remove_prefix(1);
    const std::size_t comma = word.find(',');
    if (comma == std::string_view::npos || comma == 0 || comma + 1 == word.size() ||
        !std::all_of(word.begin(), word.begin() + std::ptrdiff_t(comma), digit) ||
        !std::all_of(word.begin() + std::ptrdiff_t(comma) + 1, word.end(), digit))
      return false;
    ++words;
    at = end;
  }
}

}  // namespace

bool parseNumberWord(std::string_view word, double& value) {
  const char* start = word.data() + (!word.empty() && word.front() == '+' ? 1 : 0);
  const char* end = word.data() + word.size();
  const auto [next, error] = std::from_chars(start, end, value);
  if (next == start || next != end) return false;
  if (error == std::errc::result_out_of_range) {
    // 1e400 is a number, if not a usable one: infinite (or zero, when too small to tell).
    const std::string_view digits(start, std::size_t(end - start));
    const std::size_t exponent = digits.find_first_of("eE");
    const bool tiny =
        exponent != std::string_view::npos && digits.find('-', exponent) != std::string_view::npos;
    value = tiny ? 0.0 : (*start == '-' ? -1.0 : 1.0) * std::numeric_limits<double>::infinity();
    return true;
  }
  return error == std::errc();
}

void parseNumberRows(const std::filesystem::path& file, std::string_view text,
                     const NumberRowRules& rules,
                     const std::function<void(const std::array<double, 4>&, std::size_t)>& row,
                     const ProgressCallback& progress) {
  std::size_t position = text.substr(0, kByteOrderMark.size()) == kByteOrderMark ? 3 : 0;
  std::size_t line_number = rules.lines_before;
  std::size_t rows = 0;
  bool header_allowed = rules.header_row_allowed;
  std::size_t first_columns = 0, first_line = 0;  // the first row's
  const std::size_t min_columns = rules.min_columns;
  std::size_t next_report = 1 << 22;
  while (position < text.size()) {
    std::size_t end = text.find('\n', position);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(position, end - position);
    position = end + 1;
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    std::array<double, 4> values{};
    const int columns = parseLine(line, values);
    if (columns == 0) continue;
    if (columns < 0 && header_allowed && rows == 0) {
      header_allowed = false;
      continue;
    }
    if (columns < 0 || std::size_t(columns) < min_columns)
      throw ScanError(file, "line " + std::to_string(line_number) + ": expected at least " +
                                std::to_string(min_columns) + " numbers, got '" +
                                std::string(line.substr(0, 60)) + "'");
    if (rows == 0 && writesDecimalCommas(line))
      throw ScanError(file, "line " + std::to_string(line_number) + ": '" +
                                std::string(line.substr(0, 60)) +
                                "' writes its numbers with decimal commas; a scan's text needs a "
                                "decimal point (1.48), numbers apart by spaces, tabs, commas or "
                                "semicolons");
    if (rows == 0) {
      first_columns = std::size_t(columns);
      first_line = line_number;
    } else if (rules.same_columns && std::size_t(columns) != first_columns) {
      throw ScanError(file, "line " + std::to_string(line_number) + " holds " +
                                std::to_string(columns) + " numbers where line " +
                                std::to_string(first_line) + ", the first row, holds " +
                                std::to_string(first_columns) +
                                ": every row needs as many (x y z, or x y z intensity)");
    }
    row(values, std::size_t(columns));
    ++rows;
    if (position > next_report) {
      reportProgress(progress, 0.9 * double(position) / double(text.size()));
      next_report += 1 << 22;
    }
  }
}

}  // namespace clearway::detail
