#include "clearway/io/file_util.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <system_error>

#include "clearway/io/scan_error.h"
#include "readers.h"

namespace clearway {
namespace fs = std::filesystem;

void requireRegularFile(const fs::path& file) {
  std::error_code error;
  const fs::file_status status = fs::status(file, error);
  // A symbolic link loop or a folder without permission is not "no such file".
  if (error && error != std::errc::no_such_file_or_directory)
    throw ScanError(file, "cannot reach it: " + error.message());
  if (!fs::exists(status)) throw ScanError(file, "no such file");
  if (fs::is_directory(status)) throw ScanError(file, "is a directory, not a file to read");
  if (!fs::is_regular_file(status))
    throw ScanError(file, "not a regular file (a device, a pipe or a socket)");
}

std::string readWholeFile(const fs::path& file, std::uintmax_t max_bytes) {
  requireRegularFile(file);
  std::error_code error;
  const std::uintmax_t size = fs::file_size(file, error);
  if (error) throw ScanError(file, "cannot read its size: " + error.message());
  if (size == 0) throw ScanError(file, "empty file");
  if (size > max_bytes)
    throw ScanError(file, "file of " + std::to_string(size) +
                              " bytes is larger than the limit of " + std::to_string(max_bytes) +
                              " bytes");

  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw ScanError(file, "cannot open for reading (permissions?)");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  stream.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(stream.gcount()) != size)
    throw ScanError(
        file, "read " + std::to_string(stream.gcount()) + " of " + std::to_string(size) + " bytes");
  return bytes;
}

namespace {

// A hidden name beside `target` that no other writer picks: the process id keeps two processes
// apart, the random number two writers in one process.
fs::path temporarySibling(const fs::path& target, const char* kind) {
  std::random_device entropy;
  std::string name = ".";
  name.append(target.filename().string())
      .append(".")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(entropy()))
      .append(kind);
  return target.parent_path() / name;
}

std::string errnoText(int code) {
  return std::error_code(code, std::generic_category()).message();
}

}  // namespace

CheckedFile::CheckedFile(fs::path path, fs::path name_in_errors)
    : path_(std::move(path)), name_(std::move(name_in_errors)) {
  if (name_.empty()) name_ = path_;
  descriptor_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (descriptor_ < 0) throw ScanError(name_, "cannot create: " + errnoText(errno));
  buffer_.reserve(kBufferBytes);
}

CheckedFile::~CheckedFile() {
  if (descriptor_ >= 0) ::close(descriptor_);
}

void CheckedFile::write(std::string_view bytes) {
  if (buffer_.size() + bytes.size() <= kBufferBytes) {
    buffer_.append(bytes);
    return;
  }
  flushBuffer();
  if (bytes.size() >= kBufferBytes)
    writeAll(bytes);
  else
    buffer_.append(bytes);
}

void CheckedFile::flushBuffer() {
  writeAll(buffer_);
  buffer_.clear();
}

void CheckedFile::writeAll(std::string_view bytes) {
  while (!bytes.empty()) {
    const ::ssize_t written = ::write(descriptor_, bytes.data(), bytes.size());
    if (written < 0 && errno == EINTR) continue;
    // A short write of 0 bytes on a regular file means no space; report it as such.
    if (written <= 0) fail(written < 0 ? errno : ENOSPC);
    bytes.remove_prefix(std::size_t(written));
  }
}

void CheckedFile::fail(int code) {
  throw ScanError(name_, "cannot write: " + errnoText(code));
}

void CheckedFile::close() {
  flushBuffer();
  // fsync before the rename: after a crash the new name never points at an empty file. Its
  // failure (EIO, ENOSPC on some file systems) is a failed write.
  if (::fsync(descriptor_) != 0 && errno != EINVAL) fail(errno);
  const int descriptor = descriptor_;
  descriptor_ = -1;
  if (::close(descriptor) != 0) fail(errno);
}

void writeFileAtomically(const fs::path& target,
                         const std::function<void(const fs::path&)>& write) {
  const fs::path directory = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code error;
  if (!fs::is_directory(directory, error))
    throw ScanError(target, "cannot write: folder " + directory.string() + " does not exist");
  const fs::path temporary = temporarySibling(target, ".tmp");
  try {
    write(temporary);
    fs::rename(temporary, target);
  } catch (const fs::filesystem_error& failure) {
    fs::remove(temporary, error);
    throw ScanError(target, std::string("cannot write: ") + failure.code().message());
  } catch (...) {
    fs::remove(temporary, error);
    throw;
  }
}

void writeTextFileAtomically(const fs::path& target, const std::string& contents) {
  writeFileAtomically(target, [&](const fs::path& temporary) {
    CheckedFile file(temporary, target);
    file.write(contents);
    file.close();
  });
}

void replaceFolderAtomically(const fs::path& target,
                             const std::function<void(const fs::path&)>& write) {
  const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code error;
  if (!fs::is_directory(parent, error))
    throw ScanError(target, "cannot write: folder " + parent.string() + " does not exist");
  const fs::file_status existing = fs::symlink_status(target, error);
  if (fs::exists(existing) && !fs::is_directory(existing))
    throw ScanError(target, "cannot write: exists and is not a folder");
  const fs::path staging = temporarySibling(target, ".new");
  if (!fs::create_directory(staging, error))
    throw ScanError(target, "cannot create a folder beside it: " + error.message());
  try {
    write(staging);
  } catch (...) {
    fs::remove_all(staging, error);
    throw;
  }
  // POSIX has no atomic swap of two folders: move the old one aside, the new one in, then remove
  // the old. Between the two renames the name is missing for an instant, never mixed.
  fs::path aside;
  if (fs::exists(existing)) {
    aside = temporarySibling(target, ".old");
    fs::rename(target, aside, error);
    if (error) {
      fs::remove_all(staging, error);
      throw ScanError(target, "cannot replace the old folder: " + error.message());
    }
  }
  fs::rename(staging, target, error);
  if (error) {
    const std::string reason = error.message();
    if (!aside.empty()) fs::rename(aside, target, error);  // put the old result back
    fs::remove_all(staging, error);
    throw ScanError(target, "cannot move the new folder into place: " + reason);
  }
  if (!aside.empty()) fs::remove_all(aside, error);
}

}  // namespace clearway
