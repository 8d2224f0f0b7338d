#pragma once

// What the RoSi's ASCII line protocols share (docs/TURNTABLE.md, docs/ARM.md): one message per
// line ending in '\n' (a '\r' before it is tolerated), a command acknowledged by "OK <command>"
// or refused by "ERR <reason>".

#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace clearway::hardware::line_protocol {

struct Ok {
  std::string command;
};
struct Error {
  std::string reason;
};
using Acknowledgement = std::variant<Ok, Error>;

// "OK <command>" or "ERR <reason>"; nullopt for any other line.
std::optional<Acknowledgement> parseAcknowledgement(const std::string& line);

// Cuts a byte stream into lines; partial lines wait for the rest. Overlong lines are dropped.
class LineSplitter {
 public:
  std::vector<std::string> feed(const std::string& bytes);

 private:
  std::string pending_;
};

}  // namespace clearway::hardware::line_protocol
