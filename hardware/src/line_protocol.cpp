#include "clearway/hardware/line_protocol.h"

#include <sstream>

namespace clearway::hardware::line_protocol {
namespace {

// No reply of either protocol comes near this; a longer line is noise (a baud-rate mismatch).
constexpr std::size_t kMaxLine = 256;

}  // namespace

std::optional<Acknowledgement> parseAcknowledgement(const std::string& line) {
  std::istringstream words(line);
  std::string keyword;
  if (!(words >> keyword)) return std::nullopt;
  if (keyword == "OK") {
    Ok ok;
    words >> ok.command;
    return ok;
  }
  if (keyword == "ERR") {
    Error error;
    std::getline(words >> std::ws, error.reason);
    return error;
  }
  return std::nullopt;
}

std::vector<std::string> LineSplitter::feed(const std::string& bytes) {
  std::vector<std::string> lines;
  for (char c : bytes) {
    if (c == '\n') {
      if (!pending_.empty() && pending_.back() == '\r') pending_.pop_back();
      lines.push_back(pending_);
      pending_.clear();
    } else if (pending_.size() < kMaxLine) {
      pending_.push_back(c);
    } else {
      pending_.clear();  // an overlong line is noise: drop it and wait for the next one
    }
  }
  return lines;
}

}  // namespace clearway::hardware::line_protocol
