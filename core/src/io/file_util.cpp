#include "clearway/io/file_util.h"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <system_error>

#include "clearway/io/scan_error.h"

namespace clearway {
namespace fs = std::filesystem;

std::string readWholeFile(const fs::path& file, std::uintmax_t max_bytes) {
  std::error_code error;
  const fs::file_status status = fs::status(file, error);
  if (error || !fs::exists(status)) throw ScanError(file, "no such file");
  if (fs::is_directory(status)) throw ScanError(file, "is a directory, not a scan file");
  if (!fs::is_regular_file(status)) throw ScanError(file, "not a regular file");
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

fs::path temporarySibling(const fs::path& target) {
  std::random_device entropy;
  std::string name = ".";
  name.append(target.filename().string())
      .append(".")
      .append(std::to_string(entropy()))
      .append(".tmp");
  return target.parent_path() / name;
}

void syncFile(const fs::path& file) {
  const int descriptor = ::open(file.c_str(), O_RDONLY);
  if (descriptor < 0) return;
  ::fsync(descriptor);
  ::close(descriptor);
}

}  // namespace

void writeFileAtomically(const fs::path& target,
                         const std::function<void(const fs::path&)>& write) {
  const fs::path directory = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code error;
  if (!fs::is_directory(directory, error))
    throw ScanError(target, "cannot write: folder " + directory.string() + " does not exist");
  const fs::path temporary = temporarySibling(target);
  try {
    write(temporary);
    syncFile(temporary);
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
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    stream << contents;
    stream.flush();
    if (!stream) throw ScanError(target, "cannot write (disk full or no permission?)");
  });
}

}  // namespace clearway
