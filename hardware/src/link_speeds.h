#pragma once

// The LMS200's link speeds: the baud, the operating-mode telegram that switches the laser to it,
// and the termios speed a port follows it with. Shared by the acquisition and the emulator, so
// both sides of the line agree on what each mode means.

#include <termios.h>

#include <cstdint>
#include <optional>

#include "clearway/hardware/lms200_protocol.h"

namespace clearway::hardware::detail {

struct LinkSpeed {
  int baud;
  std::uint8_t mode;  // the operating-mode telegram that switches the LMS200
  speed_t speed;      // the port's setting to follow it
};

// 9600 baud: the LMS200's speed after power-up.
inline constexpr LinkSpeed kPowerUpSpeed{9600, lms200::kModeBaud9600, B9600};
inline constexpr LinkSpeed kLinkSpeeds[] = {kPowerUpSpeed,
                                            {19200, lms200::kModeBaud19200, B19200},
                                            {38400, lms200::kModeBaud38400, B38400},
                                            {500000, lms200::kModeBaud500k, B500000}};

inline std::optional<LinkSpeed> linkSpeedOfBaud(int baud) {
  for (const LinkSpeed& speed : kLinkSpeeds)
    if (speed.baud == baud) return speed;
  return std::nullopt;
}

// The speed an operating mode switches to; none for the modes that are not a speed.
inline std::optional<LinkSpeed> linkSpeedOfMode(std::uint8_t mode) {
  for (const LinkSpeed& speed : kLinkSpeeds)
    if (speed.mode == mode) return speed;
  return std::nullopt;
}

}  // namespace clearway::hardware::detail
