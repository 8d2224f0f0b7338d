#pragma once

// A result folder's manifest: which files belong to one `segment` run, with their sizes and
// checksums, so that a folder mixing files of two runs is refused rather than evaluated.

#include <filesystem>
#include <string>
#include <vector>

namespace clearway {

// Name of the manifest inside a result folder.
inline constexpr const char* kResultManifestName = "manifest.json";

// Writes manifest.json into `folder` listing `files` (names inside `folder`) with a fresh run id,
// each file's size and its FNV-1a 64 checksum. Throws ScanError naming the file on failure.
void writeResultManifest(const std::filesystem::path& folder,
                         const std::vector<std::string>& files);

// Checks that `folder` holds exactly what its manifest lists, byte for byte (sizes and checksums).
// Throws ScanError naming the folder or the offending file: no manifest, a file missing, changed
// or from another run.
void verifyResultFolder(const std::filesystem::path& folder);

// A file name as valid UTF-8 for JSON, losslessly: bytes that are not UTF-8 become "\xHH" and a
// backslash becomes "\\", so the original bytes can always be recovered.
std::string utf8FileName(const std::string& raw_name);

}  // namespace clearway
