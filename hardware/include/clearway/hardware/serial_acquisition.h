#pragma once

// Acquiring one RoSi scan from the real devices (or the emulator) over serial ports: the LMS200
// is put into installation mode, switched to 180 deg / 0.5 deg and continuous output; the turntable
// is homed and started; every measured-values line is tagged with the turntable angle interpolated
// at its arrival and kept until one revolution (or the requested lines) is complete. Blocking:
// the console runs it on a worker thread; clearway-cli acquire calls it directly.

#include <functional>
#include <string>

#include "clearway/progress.h"
#include "clearway/scan.h"

namespace clearway::hardware {

struct AcquisitionOptions {
  int lines = 0;  // 0 = one full revolution
  double turntable_speed_deg_s = 45.0;
  int answer_timeout_ms = 1000;  // a device silent this long is lost
  // The LMS200 starts at 9600 baud; after setup it is switched to this: 9600, 19200, 38400 or
  // 500000 (the last needs an RS-422 interface).
  int baud = 38400;
  int max_bad_telegrams = 20;  // this many corrupt telegrams in a row: the link is unusable
  // Called with the scan so far every `lines_arrived_every` lines (on the acquiring thread).
  std::function<void(const Scan&)> lines_arrived;
  int lines_arrived_every = 16;
};

struct Acquisition {
  Scan scan;              // organised: one row of 180 points per line, beta per line
  bool complete = false;  // false: `error` says why; `scan` holds the lines that arrived
  std::string error;
};

// Never throws for device trouble: it is reported in `error`, with what arrived kept. When
// `progress` asks to stop, the devices are stopped and the lines so far come back, incomplete.
Acquisition acquireRosiScan(const std::string& lms_port, const std::string& turntable_port,
                            const AcquisitionOptions& options = {},
                            const ProgressCallback& progress = {});

class Turntable;
// The same with any turntable controller behind the Turntable interface.
Acquisition acquireRosiScan(const std::string& lms_port, Turntable& turntable,
                            const AcquisitionOptions& options = {},
                            const ProgressCallback& progress = {});

}  // namespace clearway::hardware
