#include "pcd_header.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <set>
#include <sstream>

#include "clearway/io/scan_error.h"
#include "clearway/pose.h"

namespace clearway::pcd {
namespace {

// Below this largest component a VIEWPOINT quaternion is taken for zero (its direction is
// rounding noise).
constexpr double kSmallestQuaternionComponent = 1e-6;

// A binary body whose first bytes are all digits, signs, points, spaces and line breaks is text:
// binary floats of a scan hold zero bytes and bytes above 0x7f within a few points. Read as
// floats, such a body gave coordinates of 1e28 and the rest of the file unread, without a word.
constexpr std::size_t kTextProbeBytes = 256;

// A field of more elements than this is no point attribute (PCL's own histograms hold a few
// hundred).
constexpr std::uint64_t kMostElementsPerField = 4096;
bool bodyLooksLikeText(std::string_view body) {
  if (body.size() < kTextProbeBytes) return false;  // too little to tell
  return std::all_of(body.begin(), body.begin() + kTextProbeBytes, [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E' ||
           c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == 'n' || c == 'a' || c == 'i' ||
           c == 'f';
  });
}

// A piece of a line for an error message, with every byte that is not printable ASCII shown as
// '?': a binary file opened as PCD must not write its bytes to the operator's terminal.
std::string printableExcerpt(std::string_view text) {
  std::string excerpt(text);
  for (char& c : excerpt)
    if (c < ' ' || c > '~') c = '?';
  return excerpt;
}

std::vector<std::string> splitWords(std::string_view line) {
  std::vector<std::string> words;
  std::istringstream stream{std::string(line)};
  for (std::string word; stream >> word;)
    words.push_back(word);
  return words;
}

std::uint64_t parseCount(const std::filesystem::path& file, const std::string& key,
                         const std::string& text) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size())
    throw ScanError(file, "PCD header: " + key + " '" + text + "' is not a whole number");
  return value;
}

// A sensor pose with NaN or text in it would silently place the scan nowhere: refuse it.
double parseFinite(const std::filesystem::path& file, const std::string& key,
                   const std::string& text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    throw ScanError(file, "PCD header: " + key + " value '" + text + "' is not a finite number");
  return value;
}

std::uint32_t readLittleEndian32(std::string_view bytes, std::size_t offset) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

void checkBodySize(const std::filesystem::path& file, std::string_view prefix,
                   std::uint64_t file_size, const Header& header) {
  const std::uint64_t body = file_size - header.data_offset;
  const std::uint64_t expected = header.points * header.pointSize();
  if (header.encoding == Encoding::kBinary && body < expected)
    throw ScanError(file, "truncated: header promises " + std::to_string(header.points) +
                              " points (" + std::to_string(expected) + " bytes) but only " +
                              std::to_string(body) + " bytes follow");
  if (header.encoding == Encoding::kBinaryCompressed) {
    if (body < 8 || prefix.size() < header.data_offset + 8)
      throw ScanError(file, "truncated: compressed data has no size fields");
    const std::uint64_t compressed = readLittleEndian32(prefix, header.data_offset);
    const std::uint64_t uncompressed = readLittleEndian32(prefix, header.data_offset + 4);
    if (uncompressed != expected)
      throw ScanError(file, "corrupt: compressed data unpacks to " + std::to_string(uncompressed) +
                                " bytes, the header needs " + std::to_string(expected));
    if (body - 8 < compressed)
      throw ScanError(file, "truncated: " + std::to_string(compressed) +
                                " compressed bytes promised, " + std::to_string(body - 8) +
                                " present");
  }
  if (header.encoding == Encoding::kAscii && body == 0)
    throw ScanError(file, "truncated: no point data after the header");
  if (header.encoding == Encoding::kAscii) {
    // Every value takes at least one character and one separator (the file's last may lack its
    // newline): a body shorter than that cannot hold the points, whatever PCL would allocate.
    std::uint64_t values = 0;
    for (const Field& field : header.fields)
      values += std::uint64_t(field.count);
    const std::uint64_t least = header.points * values * 2 - 1;
    if (body < least)
      throw ScanError(file, "truncated: PCD header promises " + std::to_string(header.points) +
                                " points, at least " + std::to_string(least) +
                                " bytes of text, but only " + std::to_string(body) +
                                " bytes follow");
  }
}

// A binary body a whole point record or more longer than the header's points: the count is
// wrong, and the points after it were left unread without a word (a header saying 100 points of
// 7,200). Checked after the body's start, whose problems say more (text, a header keyword).
void checkBinaryBodyNotLonger(const std::filesystem::path& file, std::uint64_t file_size,
                              const Header& header) {
  if (header.encoding != Encoding::kBinary || header.pointSize() == 0) return;
  const std::uint64_t body = file_size - header.data_offset;
  const std::uint64_t expected = header.points * header.pointSize();
  if (body >= expected + header.pointSize())
    throw ScanError(file, "PCD header promises " + std::to_string(header.points) + " points (" +
                              std::to_string(expected) + " bytes) but " + std::to_string(body) +
                              " bytes follow: a wrong WIDTH, HEIGHT or POINTS?");
}

// PCL's reader parses the header again and reads the line after DATA as a header line too: when
// it starts like one of PCL's keywords ("COLUMNS", the v0.5 name of FIELDS, or any other), PCL
// replaced the fields our check saw, or sized a string by the bytes after it and read beyond its
// buffer (a crash no exception can catch: found by fuzz_pcd_reader). Real point data never
// starts with a capitalised keyword; such a file is refused before PCL reads it.
void checkBodyStart(const std::filesystem::path& file, std::string_view prefix,
                    const Header& header) {
  if (prefix.size() <= header.data_offset) return;
  const std::string_view body = prefix.substr(header.data_offset);
  for (const std::string_view keyword : {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE", "COUNT",
                                         "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"})
    if (body.substr(0, keyword.size()) == keyword)
      throw ScanError(file, "PCD body starts with the header keyword '" + std::string(keyword) +
                                "': PCL's reader would take it for a header line");
}

}  // namespace

std::size_t Header::pointSize() const {
  std::size_t total = 0;
  for (const Field& field : fields)
    total += std::size_t(field.size) * std::size_t(field.count);
  return total;
}

int Header::fieldIndex(std::string_view name) const {
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return static_cast<int>(i);
  return -1;
}

Header parseHeader(const std::filesystem::path& file, std::string_view prefix,
                   std::uint64_t file_size, std::uint64_t max_points) {
  Header header;
  std::vector<std::string> sizes, types, counts;
  bool has_points = false;
  bool has_data = false;
  std::set<std::string> seen_keys;
  std::size_t position = 0;
  const std::string_view bytes = prefix;
  while (!has_data) {
    if (position >= bytes.size())
      throw ScanError(file, "not a PCD file: no DATA line in its first " +
                                std::to_string(bytes.size()) +
                                " bytes (a header longer than that is not one)");
    std::size_t end = bytes.find('\n', position);
    if (end == std::string_view::npos) end = bytes.size();
    const std::string_view line = bytes.substr(position, end - position);
    position = std::min(end + 1, bytes.size());
    // PCL splits header lines at spaces, tabs and carriage returns only; a vertical tab or a form
    // feed, space to us, made its reader crash on a header ours had accepted (found by
    // scripts/fuzz: "\v" lines before "# .PCD v0.7").
    if (const auto control = std::find_if(line.begin(), line.end(),
                                          [](char c) {
                                            const auto byte = static_cast<unsigned char>(c);
                                            return (byte < 0x20 && c != '\t' && c != '\r') ||
                                                   byte == 0x7F;
                                          });
        control != line.end())
      throw ScanError(file, "PCD header line '" + printableExcerpt(line.substr(0, 60)) +
                                "' holds a control character: not a PCD header");
    const std::vector<std::string> words = splitWords(line);
    // A line of spaces, tabs or a carriage return alone: PCL's reader crashes on it (found by
    // scripts/fuzz; an empty line it skips, as we do).
    if (!line.empty() && words.empty())
      throw ScanError(file,
                      "PCD header holds a line of nothing but spaces or tabs: PCL's reader "
                      "cannot read such a header");
    if (words.empty() || words[0].starts_with('#')) continue;
    const std::string& key = words[0];
    // A key given twice (two WIDTH lines) took its last value here and perhaps its first in
    // another reader: which is meant, the file does not say.
    if (!seen_keys.insert(key).second)
      throw ScanError(file, "PCD header gives " + printableExcerpt(key.substr(0, 20)) + " twice");
    const std::vector<std::string> values(words.begin() + 1, words.end());
    if (key == "VERSION") {
    } else if (key == "FIELDS") {
      for (const std::string& name : values)
        header.fields.push_back({name});
    } else if (key == "SIZE") {
      sizes = values;
    } else if (key == "TYPE") {
      types = values;
    } else if (key == "COUNT") {
      counts = values;
    } else if (key == "WIDTH" && values.size() == 1) {
      header.width = parseCount(file, key, values[0]);
    } else if (key == "HEIGHT" && values.size() == 1) {
      header.height = parseCount(file, key, values[0]);
    } else if (key == "POINTS" && values.size() == 1) {
      header.points = parseCount(file, key, values[0]);
      has_points = true;
    } else if (key == "VIEWPOINT" && values.size() == 7) {
      for (std::size_t i = 0; i < 7; ++i)
        header.viewpoint[i] = parseFinite(file, "VIEWPOINT", values[i]);
      // The rotation as a unit quaternion (qw qx qy qz); a zero one is no rotation at all, and was
      // read as none (the identity) without a word.
      std::array<double, 4> rotation{header.viewpoint[3], header.viewpoint[4], header.viewpoint[5],
                                     header.viewpoint[6]};
      if (!unitQuaternion(rotation, kSmallestQuaternionComponent))
        throw ScanError(file, "VIEWPOINT's rotation (qw qx qy qz) is zero: not a rotation");
      std::copy(rotation.begin(), rotation.end(), header.viewpoint.begin() + 3);
    } else if (key == "DATA" && values.size() == 1) {
      if (values[0] == "ascii")
        header.encoding = Encoding::kAscii;
      else if (values[0] == "binary")
        header.encoding = Encoding::kBinary;
      else if (values[0] == "binary_compressed")
        header.encoding = Encoding::kBinaryCompressed;
      else
        throw ScanError(file, "PCD header: unknown DATA encoding '" + values[0] + "'");
      has_data = true;
    } else {
      throw ScanError(file, "not a PCD file: unexpected header line '" +
                                printableExcerpt(line.substr(0, 60)) + "'");
    }
  }
  header.data_offset = position;

  const std::size_t field_count = header.fields.size();
  if (field_count == 0) throw ScanError(file, "PCD header: no FIELDS");
  if (sizes.size() != field_count || types.size() != field_count ||
      (!counts.empty() && counts.size() != field_count))
    throw ScanError(file, "PCD header: FIELDS, SIZE, TYPE and COUNT disagree in length");
  for (std::size_t i = 0; i < field_count; ++i) {
    Field& field = header.fields[i];
    // Compared as read, before they are narrowed: a SIZE of 2^32 + 4 became 4 and passed.
    const std::uint64_t size = parseCount(file, "SIZE", sizes[i]);
    const std::uint64_t count = counts.empty() ? 1 : parseCount(file, "COUNT", counts[i]);
    if (size > 8 || count < 1 || count > kMostElementsPerField)
      throw ScanError(file, "PCD header: field '" + field.name + "' has an unsupported size/count");
    field.size = static_cast<int>(size);
    if (types[i].size() != 1 || std::string_view("FIU").find(types[i][0]) == std::string_view::npos)
      throw ScanError(file, "PCD header: TYPE '" + types[i] + "' is not F, I or U");
    field.type = types[i][0];
    field.count = static_cast<int>(count);
    const bool size_ok = field.type == 'F' ? (field.size == 4 || field.size == 8)
                                           : (field.size == 1 || field.size == 2 ||
                                              field.size == 4 || field.size == 8);
    if (!size_ok)
      throw ScanError(file, "PCD header: field '" + field.name + "' has an unsupported size/count");
  }
  for (const char* axis : {"x", "y", "z"}) {
    const int index = header.fieldIndex(axis);
    if (index < 0) throw ScanError(file, std::string("PCD has no '") + axis + "' field");
    if (header.fields[std::size_t(index)].type != 'F')
      throw ScanError(file, std::string("PCD field '") + axis + "' is not floating point");
  }
  if (header.width == 0 || header.height == 0)
    throw ScanError(file, "empty cloud: WIDTH or HEIGHT is 0");
  if (header.width > max_points || header.height > max_points ||
      header.width * header.height > max_points)
    throw ScanError(file, "header claims " + std::to_string(header.width) + " x " +
                              std::to_string(header.height) + " points, more than the limit of " +
                              std::to_string(max_points));
  // PCL's reader needs the line, and failed with "corrupt or shorter than its header says".
  if (!has_points) throw ScanError(file, "PCD header has no POINTS line");
  if (header.points != header.width * header.height)
    throw ScanError(
        file, "PCD header: POINTS " + std::to_string(header.points) + " is not WIDTH x HEIGHT");
  checkBodySize(file, prefix, file_size, header);
  if (header.encoding == Encoding::kBinary && bodyLooksLikeText(prefix.substr(header.data_offset)))
    throw ScanError(file,
                    "PCD header says DATA binary, but its body reads as rows of numbers "
                    "in text: is it DATA ascii?");
  checkBodyStart(file, prefix, header);
  checkBinaryBodyNotLonger(file, file_size, header);
  return header;
}

}  // namespace clearway::pcd
