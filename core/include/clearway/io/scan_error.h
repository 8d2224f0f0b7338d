#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace clearway {

// A file that cannot be read as a scan. what() is one line: "FILE: problem".
class ScanError : public std::runtime_error {
 public:
  ScanError(const std::filesystem::path& file, const std::string& problem)
      : std::runtime_error(file.string() + ": " + problem), problem_(problem) {}
  const std::string& problem() const { return problem_; }

 private:
  std::string problem_;
};

}  // namespace clearway
