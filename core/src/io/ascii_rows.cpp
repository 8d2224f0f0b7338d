#include "ascii_rows.h"

#include <charconv>
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
  const char* at = line.data();
  const char* end = line.data() + line.size();
  while (true) {
    while (at < end && isSeparator(*at))
      ++at;
    if (at == end) return columns;
    double value = 0.0;
    const char* start = (*at == '+') ? at + 1 : at;
    const auto [next, error] = std::from_chars(start, end, value);
    if (error != std::errc() || (next < end && !isSeparator(*next))) return -1;
    if (columns < 4) values[std::size_t(columns)] = value;
    ++columns;
    at = next;
  }
}

}  // namespace

void parseNumberRows(const std::filesystem::path& file, std::string_view text,
                     std::size_t min_columns,
                     const std::function<void(const std::array<double, 4>&, std::size_t)>& row,
                     const ProgressCallback& progress) {
  std::size_t position = 0;
  std::size_t line_number = 0;
  std::size_t rows = 0;
  bool header_allowed = true;
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
    row(values, std::size_t(columns));
    ++rows;
    if (position > next_report) {
      reportProgress(progress, 0.9 * double(position) / double(text.size()));
      next_report += 1 << 22;
    }
  }
}

}  // namespace clearway::detail
