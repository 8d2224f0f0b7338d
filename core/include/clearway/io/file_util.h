#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

namespace clearway {

// Reads a whole regular file. Throws ScanError for a missing, unreadable or non-regular file, an
// empty one, or one larger than `max_bytes`.
std::string readWholeFile(const std::filesystem::path& file, std::uintmax_t max_bytes);

// Calls `write(temporary_path)` to produce the file beside `target`, then renames it over `target`,
// so readers never see a half-written file. The temporary is removed if `write` throws.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path&)>& write);

// Convenience: atomically writes `contents` to `target`.
void writeTextFileAtomically(const std::filesystem::path& target, const std::string& contents);

}  // namespace clearway
