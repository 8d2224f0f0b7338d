// The LMS200 byte-stream parser on arbitrary bytes, fed in pieces as a serial port delivers them;
// every telegram it returns is decoded as measured values (refusal by std::invalid_argument).

#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "clearway/hardware/lms200_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace lms = clearway::hardware::lms200;
  lms::Parser parser;
  // The first byte chooses the piece size, so fragments split telegrams everywhere.
  const std::size_t piece = size > 0 ? std::size_t(data[0] % 64) + 1 : 1;
  for (std::size_t at = 0; at < size; at += piece) {
    const std::size_t length = at + piece <= size ? piece : size - at;
    for (const lms::ParseEvent& event : parser.feed(data + at, length)) {
      if (event.kind != lms::ParseEvent::Kind::kTelegram) continue;
      try {
        const lms::MeasuredValues values = lms::decodeMeasuredValues(event.telegram);
        for (const auto& range : values.ranges)
          if (range && !(*range >= 0.0)) __builtin_trap();
      } catch (const std::invalid_argument&) {
      }
    }
  }
  return 0;
}
