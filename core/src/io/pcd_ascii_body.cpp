#include "pcd_ascii_body.h"

#include <algorithm>
#include <fstream>
#include <string>
#include <string_view>

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

}  // namespace

void checkAsciiBody(const std::filesystem::path& file, const Header& header) {
  std::size_t per_row = 0;
  for (const Field& field : header.fields)
    per_row += std::size_t(std::max(field.count, 0));
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
      if (double value = 0.0; !detail::parseNumberWord(view.substr(start, end - start), value))
        throw ScanError(file, "PCD line " + std::to_string(line_number) + ": " +
                                  quoted(view.substr(start, end - start)) + " is not a number");
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
