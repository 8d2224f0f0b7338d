#include "clearway/io/result_manifest.h"

#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"

namespace clearway {
namespace {

// Result files are small (maps, a mesh, one byte per point); more than this is not one of ours.
constexpr std::uintmax_t kMaxResultFileBytes = 4ULL << 30;

// FNV-1a, 64 bit: a checksum to tell files apart, not a defence against tampering.
std::string checksum(const std::string& bytes) {
  constexpr std::uint64_t kOffsetBasis = 14695981039346656037ULL;
  constexpr std::uint64_t kPrime = 1099511628211ULL;
  std::uint64_t hash = kOffsetBasis;
  for (const char byte : bytes) {
    hash ^= static_cast<unsigned char>(byte);
    hash *= kPrime;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string newRunId() {
  std::random_device entropy;
  char text[17];
  std::snprintf(text, sizeof text, "%08x%08x", entropy(), entropy());
  return text;
}

// Length of the valid UTF-8 sequence starting at `at`, or 0 when the bytes there are not one.
std::size_t utf8SequenceLength(const std::string& text, std::size_t at) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(at);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  std::uint32_t code = 0;
  if ((lead & 0xE0) == 0xC0) {
    length = 2;
    code = lead & 0x1F;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3;
    code = lead & 0x0F;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4;
    code = lead & 0x07;
  } else {
    return 0;
  }
  if (at + length > text.size()) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(at + i) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(at + i) & 0x3F);
  }
  // Overlong forms, surrogates and code points past U+10FFFF are not valid UTF-8.
  static constexpr std::uint32_t kLeast[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < kLeast[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

}  // namespace

std::string utf8FileName(const std::string& raw_name) {
  std::string out;
  for (std::size_t at = 0; at < raw_name.size();) {
    if (raw_name[at] == '\\') {
      out += "\\\\";
      ++at;
      continue;
    }
    const std::size_t length = utf8SequenceLength(raw_name, at);
    if (length == 0) {
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", static_cast<unsigned char>(raw_name[at]));
      out += escaped;
      ++at;
    } else {
      out.append(raw_name, at, length);
      at += length;
    }
  }
  return out;
}

void writeResultManifest(const std::filesystem::path& folder,
                         const std::vector<std::string>& files) {
  nlohmann::ordered_json manifest;
  manifest["run_id"] = newRunId();
  nlohmann::ordered_json entries = nlohmann::ordered_json::object();
  for (const std::string& name : files) {
    const std::string bytes = readWholeFile(folder / name, kMaxResultFileBytes);
    entries[name] = {{"bytes", bytes.size()}, {"fnv1a64", checksum(bytes)}};
  }
  manifest["files"] = entries;
  writeTextFileAtomically(folder / kResultManifestName, manifest.dump(2) + "\n");
}

void verifyResultFolder(const std::filesystem::path& folder) {
  const std::filesystem::path manifest_file = folder / kResultManifestName;
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error))
    throw ScanError(folder, "not a result folder (no such folder)");
  if (!std::filesystem::exists(folder / "report.json", error))
    throw ScanError(folder / "report.json", "no such file: not a result folder");
  if (!std::filesystem::exists(manifest_file, error))
    throw ScanError(folder, std::string("not a complete result folder: no ") + kResultManifestName +
                                " (interrupted, or written by hand?)");
  nlohmann::json manifest;
  try {
    manifest = nlohmann::json::parse(readWholeFile(manifest_file, 1 << 20));
    const std::string run_id = manifest.at("run_id").get<std::string>();
    // A manifest of no files (`"files": {}`) vouched for a folder of any files.
    if (!manifest.at("files").is_object() || !manifest.at("files").contains("report.json"))
      throw ScanError(manifest_file, "does not list report.json: it vouches for nothing");
    for (const auto& [name, entry] : manifest.at("files").items()) {
      if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
        throw ScanError(manifest_file, "lists '" + name + "', which is not a file in the folder");
      const std::filesystem::path file = folder / name;
      if (!std::filesystem::exists(file, error))
        throw ScanError(file, "missing from the result of run " + run_id);
      const std::string bytes = readWholeFile(file, kMaxResultFileBytes);
      if (bytes.size() != entry.at("bytes").get<std::size_t>() ||
          checksum(bytes) != entry.at("fnv1a64").get<std::string>())
        throw ScanError(file, "does not belong to run " + run_id +
                                  " (size or checksum differs from " + kResultManifestName +
                                  "): the folder mixes two results");
    }
  } catch (const nlohmann::json::exception& failure) {
    throw ScanError(manifest_file, std::string("unreadable manifest: ") + failure.what());
  }
}

}  // namespace clearway
