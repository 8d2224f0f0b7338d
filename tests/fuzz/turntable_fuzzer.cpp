// The turntable's reply lines on arbitrary bytes: split into lines as the port delivers them,
// each parsed; angles that come out must lie in [0, 360).

#include <cstddef>
#include <cstdint>
#include <string>

#include "clearway/hardware/turntable_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace turntable = clearway::hardware::turntable;
  turntable::LineSplitter splitter;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  for (const std::string& line : splitter.feed(bytes)) {
    const auto reply = turntable::parseReply(line);
    if (!reply) continue;
    if (const auto* sample = std::get_if<turntable::AngleSample>(&*reply))
      if (!(sample->angle_deg >= 0.0 && sample->angle_deg < 360.0)) __builtin_trap();
  }
  return 0;
}
