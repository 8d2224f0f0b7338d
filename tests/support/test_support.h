#pragma once

// Helpers shared by the tests: a temporary folder per test, the real scans beside the project,
// and running clearway-cli as a user would.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace clearway::test {

// A fresh folder, removed when the object dies.
class TemporaryDirectory {
 public:
  TemporaryDirectory();
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

void writeBytes(const std::filesystem::path& file, const std::string& bytes);
std::string readBytes(const std::filesystem::path& file);

// A test that writes files of its own into a fresh folder.
class FileFolderTest : public ::testing::Test {
 protected:
  TemporaryDirectory directory;
  // Writes `bytes` to `name` in the folder; returns its path.
  std::filesystem::path write(const std::string& name, const std::string& bytes) {
    const auto file = directory / name;
    writeBytes(file, bytes);
    return file;
  }
};

// Path of a real scan under ../shared/data/real, or empty when the folder is absent.
std::filesystem::path realScan(const std::string& relative);

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
// Runs clearway-cli with `arguments` (shell-quoted here) and captures its output.
CommandResult runCli(const std::string& arguments);
std::string shellQuote(const std::string& text);

}  // namespace clearway::test

// Skips the test with a clear message when a real scan is not present.
#define CLEARWAY_REAL_SCAN_OR_SKIP(variable, relative)                                        \
  const std::filesystem::path variable = ::clearway::test::realScan(relative);                \
  if (variable.empty())                                                                       \
  GTEST_SKIP() << "real scan " << (relative) << " not found under " << CLEARWAY_REAL_DATA_DIR \
               << " (../shared absent?)"
