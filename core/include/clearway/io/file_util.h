#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace clearway {

// Throws ScanError unless `file` is a regular file (or a link to one): missing, unreachable (a
// link loop), a directory, or a pipe, device or socket, which a reader would wait on for ever or
// read without end.
void requireRegularFile(const std::filesystem::path& file);

// Reads a whole regular file. Throws ScanError for a missing, unreadable or non-regular file, an
// empty one, or one larger than `max_bytes`.
std::string readWholeFile(const std::filesystem::path& file, std::uintmax_t max_bytes);

// A file written through plain buffered write(2) calls, every one checked: a full disk or a file
// size limit is a ScanError naming the file ("cannot write: No space left on device"), never a
// signal. Nothing is memory-mapped. close() flushes, fsyncs and closes; a file never closed is
// simply closed (callers remove it).
class CheckedFile {
 public:
  // `name_in_errors` is the file the user asked for (the temporary's target); defaults to `path`.
  explicit CheckedFile(std::filesystem::path path, std::filesystem::path name_in_errors = {});
  ~CheckedFile();
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;

  void write(std::string_view bytes);
  void close();

 private:
  // Bytes gathered before one write(2): large enough that a scan takes a few hundred calls.
  static constexpr std::size_t kBufferBytes = 1 << 20;
  void flushBuffer();
  void writeAll(std::string_view bytes);
  [[noreturn]] void fail(int code);

  std::filesystem::path path_;
  std::filesystem::path name_;
  std::string buffer_;
  int descriptor_ = -1;
};

// Calls `write(temporary_path)` to produce the file beside `target`, then renames it over `target`,
// so readers never see a half-written file. The temporary is removed if `write` throws.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path&)>& write);

// Convenience: atomically writes `contents` to `target` through a CheckedFile.
void writeTextFileAtomically(const std::filesystem::path& target, const std::string& contents);

// Calls `write(staging_folder)` to fill a new folder beside `target`, then puts it in place of
// `target` (an old folder is moved aside, the new one renamed in, the old one removed), so a
// reader sees the old folder or the new one, never a mix. If `write` throws, the staging folder is
// removed and an old `target` stays as it was.
void replaceFolderAtomically(const std::filesystem::path& target,
                             const std::function<void(const std::filesystem::path&)>& write);

}  // namespace clearway
