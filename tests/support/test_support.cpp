#include "test_support.h"

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

namespace clearway::test {
namespace fs = std::filesystem;

TemporaryDirectory::TemporaryDirectory() {
  std::random_device entropy;
  path_ = fs::temp_directory_path() / ("clearway-test-" + std::to_string(entropy()));
  fs::create_directories(path_);
}

TemporaryDirectory::~TemporaryDirectory() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

void writeBytes(const fs::path& file, const std::string& bytes) {
  std::ofstream stream(file, std::ios::binary | std::ios::trunc);
  stream << bytes;
}

std::string readBytes(const fs::path& file) {
  std::ifstream stream(file, std::ios::binary);
  std::ostringstream contents;
  contents << stream.rdbuf();
  return contents.str();
}

fs::path realScan(const std::string& relative) {
  const fs::path path = fs::path(CLEARWAY_REAL_DATA_DIR) / relative;
  return fs::exists(path) ? path : fs::path();
}

std::string shellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text)
    quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

CommandResult runCli(const std::string& arguments) {
  static int counter = 0;
  const fs::path err_file =
      fs::temp_directory_path() /
      ("clearway-cli-err-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  const std::string command =
      shellQuote(CLEARWAY_CLI) + " " + arguments + " 2>" + shellQuote(err_file.string());
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
    result.out.append(buffer, n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.err = readBytes(err_file);
  fs::remove(err_file);
  return result;
}

}  // namespace clearway::test
