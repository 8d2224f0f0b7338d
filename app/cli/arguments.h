#pragma once

// A small command-line reader for clearway-cli: positional arguments and --name [value] options.
// Mistakes throw UsageError, which main() turns into exit code 2.

#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace clearway::cli {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Arguments {
 public:
  // `flags` take no value; `options` take one (given as --name VALUE or --name=VALUE).
  Arguments(const std::vector<std::string>& words, const std::set<std::string>& flags,
            const std::set<std::string>& options);

  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  std::optional<std::string> option(const std::string& name) const;
  double number(const std::string& name, double fallback, double min, double max) const;
  long integer(const std::string& name, long fallback, long min, long max) const;
  const std::vector<std::string>& positional() const { return positional_; }
  // Exactly `count` positional arguments, or a UsageError naming what was expected.
  void expectPositional(std::size_t count, const std::string& what) const;

 private:
  std::set<std::string> flags_;
  std::vector<std::pair<std::string, std::string>> options_;
  std::vector<std::string> positional_;
};

}  // namespace clearway::cli
