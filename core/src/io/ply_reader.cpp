// PLY vertices (ascii, binary little/big endian). Our own reader rather than PCL's: we need the
// element counts checked against the file's size before anything is allocated, and only the vertex
// element matters to a scan.

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <sstream>
#include <string_view>

#include "ascii_rows.h"
#include "clearway/io/file_util.h"
#include "clearway/io/scan_lines.h"
#include "readers.h"

namespace clearway::detail {
namespace {

// A PLY header longer than this is not one.
constexpr std::size_t kMaxHeaderBytes = 1'000'000;
constexpr std::uintmax_t kMaxPlyBytes = 8ULL << 30;

enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

struct PlyProperty {
  std::string name;
  std::string type;  // char uchar short ushort int uint float double (and int8... aliases)
  bool is_list = false;
  int size = 0;  // bytes of one scalar
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t recordSize() const {
    std::size_t size = 0;
    for (const PlyProperty& property : properties)
      size += std::size_t(property.size);
    return size;
  }
};

int scalarSize(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

double readScalar(const char* at, const std::string& type, bool swap) {
  char buffer[8] = {};
  // At most the buffer (scalarSize never says more): bounded, so the compiler can see it.
  const std::size_t size = std::min(std::size_t(scalarSize(type)), sizeof buffer);
  std::memcpy(buffer, at, size);
  if (swap)
    for (std::size_t i = 0; i < size / 2; ++i)
      std::swap(buffer[i], buffer[size - 1 - i]);
  auto as = [&buffer]<typename T>(T) {
    T value;
    std::memcpy(&value, buffer, sizeof(T));
    return static_cast<double>(value);
  };
  if (type == "char" || type == "int8") return as(std::int8_t{});
  if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
  if (type == "short" || type == "int16") return as(std::int16_t{});
  if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
  if (type == "int" || type == "int32") return as(std::int32_t{});
  if (type == "uint" || type == "uint32") return as(std::uint32_t{});
  if (type == "float" || type == "float32") return as(float{});
  return as(double{});
}

bool hasListProperty(const PlyElement& element) {
  return std::any_of(element.properties.begin(), element.properties.end(),
                     [](const PlyProperty& property) { return property.is_list; });
}

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
};

PlyHeader parsePlyHeader(const std::filesystem::path& file, const std::string& bytes) {
  if (!bytes.starts_with("ply"))
    throw ScanError(file, "not a PLY file: it does not start with 'ply'");
  PlyHeader header;
  bool has_format = false;
  std::size_t position = 0;
  while (true) {
    const std::size_t end = bytes.find('\n', position);
    if (end == std::string::npos || end > kMaxHeaderBytes)
      throw ScanError(file, "not a PLY file: no end_header in its first " +
                                std::to_string(std::min(bytes.size(), kMaxHeaderBytes)) +
                                " bytes (a header longer than that is not one)");
    std::istringstream line(bytes.substr(position, end - position));
    position = end + 1;
    std::string keyword;
    line >> keyword;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      std::string name;
      line >> name;
      if (name == "ascii")
        header.format = PlyFormat::kAscii;
      else if (name == "binary_little_endian")
        header.format = PlyFormat::kBinaryLittle;
      else if (name == "binary_big_endian")
        header.format = PlyFormat::kBinaryBig;
      else
        throw ScanError(file, "PLY: unknown format '" + name + "'");
      has_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      std::string count, rest;
      if (!(line >> element.name >> count) || (line >> rest))
        throw ScanError(file, "PLY: malformed element line");
      // A whole number: ">>" read "1.5" as 1 and "1e3" as 1, and the rest of the file was not read.
      const auto [parsed_to, error] =
          std::from_chars(count.data(), count.data() + count.size(), element.count);
      if (error != std::errc() || parsed_to != count.data() + count.size())
        throw ScanError(file, "PLY: element " + element.name + "'s count '" + count +
                                  "' is not a whole number");
      header.elements.push_back(element);
    } else if (keyword == "property") {
      if (header.elements.empty()) throw ScanError(file, "PLY: property before any element");
      PlyProperty property;
      line >> property.type;
      if (property.type == "list") {
        std::string count_type;
        line >> count_type >> property.type;
        property.is_list = true;
      }
      line >> property.name;
      property.size = scalarSize(property.type);
      if (property.size == 0)
        throw ScanError(file, "PLY: unknown property type '" + property.type + "'");
      header.elements.back().properties.push_back(property);
    }
    // comment, obj_info and ply itself carry nothing we need.
  }
  if (!has_format) throw ScanError(file, "PLY: no format line");
  header.body_offset = position;
  return header;
}

// Refuses counts the file cannot hold: binary records must fit, and an ascii vertex needs at
// least one character and one separator per property.
void checkSizes(const std::filesystem::path& file, const PlyHeader& header,
                const PlyElement& vertex, std::uintmax_t file_size) {
  const std::uintmax_t body = file_size - std::min<std::uintmax_t>(file_size, header.body_offset);
  if (header.format == PlyFormat::kAscii) {
    const std::uintmax_t least = vertex.count * vertex.properties.size() * 2 - 1;
    if (body < least)
      throw ScanError(file, "truncated: " + std::to_string(vertex.count) +
                                " vertices need at least " + std::to_string(least) +
                                " bytes of text, " + std::to_string(body) + " follow the header");
    return;
  }
  std::uintmax_t offset = 0;
  for (const PlyElement& element : header.elements) {
    const std::uintmax_t record = element.recordSize();
    if (record > 0 && element.count > (body - std::min(body, offset)) / record)
      throw ScanError(file, "truncated: " + std::to_string(element.count) + " " + element.name +
                                " records of " + std::to_string(record) +
                                " bytes do not fit in the file");
    if (&element == &vertex) return;
    offset += record * element.count;
  }
}

// One ascii PLY row into `row`: true when it holds exactly row.size() numbers (`values` set to
// that) or none (a blank line, `values` 0).
bool readPlyRow(std::string_view line, std::vector<double>& row, std::size_t& values) {
  values = 0;
  std::size_t at = 0;
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (true) {
    while (at < line.size() && space(line[at]))
      ++at;
    if (at == line.size()) return values == 0 || values == row.size();
    std::size_t end = at;
    while (end < line.size() && !space(line[end]))
      ++end;
    if (values == row.size()) return false;  // more numbers than properties
    if (!parseNumberWord(line.substr(at, end - at), row[values])) return false;
    ++values;
    at = end;
  }
}

// The rows of an ascii PLY's vertices (the first element): its first vertex.count lines that are
// not blank, up to the end of the last, and how many rows follow them (up to the end of the file).
// Throws when the file has fewer.
struct AsciiVertexRows {
  std::string_view rows;
  std::size_t rows_after = 0;
};
AsciiVertexRows asciiVertexRows(const std::filesystem::path& file, std::string_view bytes,
                                const PlyHeader& header, const PlyElement& vertex) {
  const auto blank = [](std::string_view line) {
    return line.find_first_not_of(" \t\r") == std::string_view::npos;
  };
  std::size_t position = header.body_offset, rows = 0, rows_end = position, rows_after = 0;
  while (position < bytes.size()) {
    std::size_t end = bytes.find('\n', position);
    if (end == std::string_view::npos) end = bytes.size();
    const bool row = !blank(bytes.substr(position, end - position));
    position = std::min(end + 1, bytes.size());
    if (rows < vertex.count) {
      rows += row;
      rows_end = position;
    } else {
      rows_after += row;
    }
  }
  if (rows < vertex.count)
    throw ScanError(file, "truncated: " + std::to_string(rows) + " of " +
                              std::to_string(vertex.count) + " vertices present");
  return {bytes.substr(header.body_offset, rows_end - header.body_offset), rows_after};
}

int propertyIndex(const PlyElement& element, std::initializer_list<const char*> names) {
  for (const char* name : names)
    for (std::size_t i = 0; i < element.properties.size(); ++i)
      if (element.properties[i].name == name && !element.properties[i].is_list) return int(i);
  return -1;
}

}  // namespace

Scan readPly(const std::filesystem::path& file, const LoadOptions& options) {
  // The header alone first: the format is recognised and every count checked against the file's
  // size before the body is read or anything allocated for it.
  std::uintmax_t file_size = 0;
  const PlyHeader header = parsePlyHeader(file, readFilePrefix(file, kMaxHeaderBytes, file_size));
  const auto vertex_it = std::find_if(header.elements.begin(), header.elements.end(),
                                      [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex_it == header.elements.end()) throw ScanError(file, "PLY has no vertex element");
  const PlyElement& vertex = *vertex_it;
  if (vertex.count == 0) throw ScanError(file, "empty cloud: PLY has 0 vertices");
  if (vertex.count > options.max_points)
    throw ScanError(file, "header claims " + std::to_string(vertex.count) +
                              " vertices, more than the limit of " +
                              std::to_string(options.max_points));
  const int ix = propertyIndex(vertex, {"x"});
  const int iy = propertyIndex(vertex, {"y"});
  const int iz = propertyIndex(vertex, {"z"});
  if (ix < 0 || iy < 0 || iz < 0) throw ScanError(file, "PLY vertices have no x, y, z");
  if (hasListProperty(vertex))
    throw ScanError(file, "PLY: list properties on vertices are not supported");
  checkSizes(file, header, vertex, file_size);
  refuseBeyondMemory(file, vertex.count, file_size, options);
  const std::string bytes = readWholeFile(file, kMaxPlyBytes);
  const int ii =
      propertyIndex(vertex, {"intensity", "scalar_intensity", "remission", "reflectance"});
  int ir = -1;  // a multi-beam frame's ring number
  for (const char* name : kRingFieldNames)
    if (ir < 0) ir = propertyIndex(vertex, {name});
  std::vector<double> ring_numbers;

  Scan scan;
  if (ii >= 0) scan.intensity.reserve(vertex.count);
  if (ir >= 0) ring_numbers.reserve(vertex.count);
  if (header.format == PlyFormat::kAscii) {
    // Vertices come first in every PLY we meet; a scan with faces before vertices is not one.
    if (&vertex != &header.elements.front())
      throw ScanError(file, "PLY: elements before the vertices are not supported in ascii files");
    const AsciiVertexRows vertex_rows = asciiVertexRows(file, bytes, header, vertex);
    if (vertex.properties.size() > 4 || ix > 3 || iy > 3 || iz > 3 || ii > 3 || ir > 3) {
      // Rows with many columns: each a line of exactly one number per property, as the rows
      // below (a stream read across lines took a row cut short with the next one's values).
      std::size_t line_number = std::size_t(
          std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(header.body_offset), '\n'));
      std::size_t position = header.body_offset;
      const std::size_t rows_end = header.body_offset + vertex_rows.rows.size();
      std::vector<double> row(vertex.properties.size());
      for (std::uint64_t v = 0; v < vertex.count;) {
        if (position >= rows_end)
          throw ScanError(file, "truncated: " + std::to_string(v) + " of " +
                                    std::to_string(vertex.count) + " vertices present");
        std::size_t end = bytes.find('\n', position);
        if (end == std::string::npos || end > rows_end) end = rows_end;
        const std::string_view line(bytes.data() + position, end - position);
        position = end + 1;
        ++line_number;
        std::size_t values = 0;
        if (!readPlyRow(line, row, values))
          throw ScanError(file, "line " + std::to_string(line_number) + ": PLY vertex " +
                                    std::to_string(v) + " is not " + std::to_string(row.size()) +
                                    " numbers, one per property");
        if (values == 0) continue;  // a blank line
        appendPoint(scan, float(row[std::size_t(ix)]), float(row[std::size_t(iy)]),
                    float(row[std::size_t(iz)]));
        if (ii >= 0) scan.intensity.push_back(float(row[std::size_t(ii)]));
        if (ir >= 0) ring_numbers.push_back(row[std::size_t(ir)]);
        ++v;
      }
    } else {
      const std::string_view body = vertex_rows.rows;
      std::uint64_t read = 0;
      NumberRowRules rules;
      rules.min_columns = vertex.properties.size();
      rules.header_row_allowed = false;  // the header said what follows: a word is an error
      rules.same_columns = false;        // each vertex is checked against the properties below
      rules.lines_before = std::size_t(
          std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(header.body_offset), '\n'));
      parseNumberRows(
          file, body, rules,
          [&](const std::array<double, 4>& v, std::size_t columns) {
            if (columns != vertex.properties.size())
              throw ScanError(file, "PLY vertex " + std::to_string(read) + " has " +
                                        std::to_string(columns) + " values where its " +
                                        std::to_string(vertex.properties.size()) +
                                        " properties take one each");
            ++read;
            appendPoint(scan, float(v[std::size_t(ix)]), float(v[std::size_t(iy)]),
                        float(v[std::size_t(iz)]));
            if (ii >= 0) scan.intensity.push_back(float(v[std::size_t(ii)]));
            if (ir >= 0) ring_numbers.push_back(v[std::size_t(ir)]);
          },
          options.progress);
      if (read < vertex.count)
        throw ScanError(file, "truncated: " + std::to_string(read) + " of " +
                                  std::to_string(vertex.count) + " vertices present");
    }
    // With no element after the vertices, rows after them mean the header's count is wrong: they
    // were left unread without a word. Said once the vertices read, whose problems say more.
    if (&vertex == &header.elements.back() && vertex_rows.rows_after > 0)
      throw ScanError(file, "PLY holds " + std::to_string(vertex_rows.rows_after) +
                                " rows after its " + std::to_string(vertex.count) +
                                " vertices, and no element they belong to: a wrong vertex count?");
  } else {
    std::size_t offset = header.body_offset;
    for (const PlyElement& element : header.elements) {
      if (&element == &vertex) break;
      if (hasListProperty(element))
        throw ScanError(file, "PLY: list elements before the vertices are not supported");
      offset += element.recordSize() * element.count;
    }
    const std::size_t record = vertex.recordSize();
    std::vector<std::size_t> property_offsets;
    std::size_t running = 0;
    for (const PlyProperty& property : vertex.properties) {
      property_offsets.push_back(running);
      running += std::size_t(property.size);
    }
    const bool swap =
        (header.format == PlyFormat::kBinaryBig) != (std::endian::native == std::endian::big);
    scan.points.reserve(vertex.count);
    scan.status.reserve(vertex.count);
    auto value = [&](const char* at, int index) {
      const PlyProperty& property = vertex.properties[std::size_t(index)];
      return readScalar(at + property_offsets[std::size_t(index)], property.type, swap);
    };
    // Vertices last, with at least another vertex's worth of bytes after them: the header does
    // not say what the file holds (a wrong count or property type), and three quarters of a file
    // were left unread without a word.
    const std::size_t vertices_end = offset + record * vertex.count;
    if (&vertex == &header.elements.back() && bytes.size() >= vertices_end + record)
      throw ScanError(file, "PLY holds " + std::to_string(bytes.size() - vertices_end) +
                                " bytes after its last vertex: more than its header declares "
                                "(a wrong vertex count or property type?)");
    for (std::uint64_t v = 0; v < vertex.count; ++v) {
      const char* at = bytes.data() + offset + v * record;
      appendPoint(scan, float(value(at, ix)), float(value(at, iy)), float(value(at, iz)));
      if (ii >= 0) scan.intensity.push_back(float(value(at, ii)));
      if (ir >= 0) ring_numbers.push_back(value(at, ir));
    }
  }
  if (ir >= 0)
    if (const std::string why_not = groupIntoRings(scan, ring_numbers); !why_not.empty())
      throw ScanError(file,
                      "PLY property '" + vertex.properties[std::size_t(ir)].name + "': " + why_not);
  scan.metadata.format = header.format == PlyFormat::kAscii ? "ply ascii" : "ply binary";
  scan.metadata.frame = "as stored: metres";
  return scan;
}

}  // namespace clearway::detail
