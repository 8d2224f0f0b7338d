#include "pcd_ascii_body.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ascii_rows.h"
#include "clearway/io/scan_error.h"

namespace clearway::pcd {
namespace {

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

std::string quoted(std::string_view line) {
  constexpr std::size_t kShown = 60;
  std::string text(line.substr(0, kShown));
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20) c = '?';
  return "'" + text + (line.size() > kShown ? "...'" : "'");
}

// The whole numbers a field of integer TYPE (I or U) and SIZE (1, 2, 4 or 8) holds.
struct IntegerRange {
  double least = 0.0, most = 0.0;  // as doubles (2^64 - 1 rounds up: the bound is not exact there)
  std::string text;                // "from ... to ..."
};
std::optional<IntegerRange> integerRange(const Field& field) {
  if (field.type == 'F') return std::nullopt;
  const int bits = 8 * field.size;
  if (field.type == 'U') {
    const std::uint64_t most = bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
    return IntegerRange{0.0, double(most), "from 0 to " + std::to_string(most)};
  }
  const std::int64_t most = std::int64_t((std::uint64_t{1} << (bits - 1)) - 1);
  const std::int64_t least = -most - 1;
  return IntegerRange{double(least), double(most),
                      "from " + std::to_string(least) + " to " + std::to_string(most)};
}

}  // namespace

void checkAsciiBody(const std::filesystem::path& file, const Header& header) {
  // Per column of a row: its field. PCL reads a "nan", 1e10 or 2.5 in an integer field (a ring
  // number) as whatever its cast makes of it, so such a value is refused here, naming its field.
  std::vector<const Field*> column_field;
  for (const Field& field : header.fields)
    column_field.insert(column_field.end(), std::size_t(std::max(field.count, 0)), &field);
  const std::size_t per_row = column_field.size();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ScanError(file, "cannot open the file");
  // Line numbers as an editor shows them: the header's lines first.
  std::string text(header.data_offset, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  std::size_t line_number = std::size_t(std::count(text.begin(), text.end(), '\n'));
  std::uint64_t rows = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++line_number;
    std::size_t words = 0, start = 0;
    const std::string_view view(line);
    while (start < view.size()) {
      while (start < view.size() && isSpace(view[start]))
        ++start;
      if (start == view.size()) break;
      std::size_t end = start;
      while (end < view.size() && !isSpace(view[end]))
        ++end;
      double value = 0.0;
      if (!detail::parseNumberWord(view.substr(start, end - start), value))
        throw ScanError(file, "PCD line " + std::to_string(line_number) + ": " +
                                  quoted(view.substr(start, end - start)) + " is not a number");
      if (words < per_row)
        if (const auto range = integerRange(*column_field[words]);
            range && !(value >= range->least && value <= range->most && value == std::floor(value)))
          throw ScanError(file, "PCD line " + std::to_string(line_number) + ": field '" +
                                    column_field[words]->name + "' (TYPE " +
                                    column_field[words]->type + " SIZE " +
                                    std::to_string(column_field[words]->size) + ") holds " +
                                    quoted(view.substr(start, end - start)) +
                                    ", not a whole number " + range->text);
      ++words;
      start = end;
    }
    if (words == 0) continue;  // a blank line
    if (words != per_row)
      throw ScanError(file, "PCD line " + std::to_string(line_number) + ": " +
                                std::to_string(words) + " numbers where the header's fields take " +
                                std::to_string(per_row) + " (" + quoted(view) +
                                "): a row cut short, or the file cut off");
    if (++rows > header.points)
      throw ScanError(file, "PCD body holds more rows than its header's POINTS " +
                                std::to_string(header.points) + " (line " +
                                std::to_string(line_number) + ")");
  }
  if (rows < header.points)
    throw ScanError(file, "PCD body holds " + std::to_string(rows) +
                              " rows where its header says " + "POINTS " +
                              std::to_string(header.points) + ": the file is cut off");
}

}  // namespace clearway::pcd
