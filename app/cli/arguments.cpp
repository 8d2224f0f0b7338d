#include "arguments.h"

#include <charconv>

#include "clearway/segmentation/params.h"

namespace clearway::cli {

Arguments::Arguments(const std::vector<std::string>& words, const std::set<std::string>& flags,
                     const std::set<std::string>& options) {
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::string& word = words[i];
    // Short options are single letters: -o FILE.
    const bool is_short = word.size() == 2 && word[0] == '-' && word[1] != '-';
    if ((!word.starts_with("--") && !is_short) || word == "--") {
      positional_.push_back(word);
      continue;
    }
    std::string name = word.substr(is_short ? 1 : 2);
    std::optional<std::string> inline_value;
    if (const auto equals = name.find('='); equals != std::string::npos) {
      inline_value = name.substr(equals + 1);
      name = name.substr(0, equals);
    }
    if (flags.count(name)) {
      if (inline_value) throw UsageError("--" + name + " takes no value");
      flags_.insert(name);
    } else if (options.count(name)) {
      if (inline_value) {
        options_.emplace_back(name, *inline_value);
      } else {
        if (i + 1 >= words.size()) throw UsageError("--" + name + " needs a value");
        options_.emplace_back(name, words[++i]);
      }
    } else {
      throw UsageError("unknown option --" + name);
    }
  }
}

std::optional<std::string> Arguments::option(const std::string& name) const {
  std::optional<std::string> value;
  for (const auto& [key, given] : options_)
    if (key == name) value = given;  // the last one wins, as in most tools
  return value;
}

double Arguments::number(const std::string& name, double fallback, double min, double max) const {
  const auto text = option(name);
  if (!text) return fallback;
  double value = 0.0;
  const auto [end, error] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (error != std::errc() || end != text->data() + text->size())
    throw UsageError("--" + name + " '" + *text + "' is not a number");
  if (!(value >= min && value <= max))
    throw UsageError("--" + name + " " + *text + " is outside " + readableNumber(min) + " .. " +
                     readableNumber(max));
  return value;
}

long Arguments::integer(const std::string& name, long fallback, long min, long max) const {
  const auto text = option(name);
  if (!text) return fallback;
  long value = 0;
  const auto [end, error] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (error != std::errc() || end != text->data() + text->size())
    throw UsageError("--" + name + " '" + *text + "' is not a whole number");
  if (value < min || value > max)
    throw UsageError("--" + name + " " + *text + " is outside " + std::to_string(min) + " .. " +
                     std::to_string(max));
  return value;
}

void Arguments::expectPositional(std::size_t count, const std::string& what) const {
  if (positional_.size() != count) throw UsageError("expected " + what);
}

}  // namespace clearway::cli
