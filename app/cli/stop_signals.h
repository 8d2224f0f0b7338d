#pragma once

// SIGINT/SIGTERM during an acquisition: the handler only records the signal and writes a byte
// into a pipe (both async-signal-safe) that the acquisition polls or a QSocketNotifier watches;
// the devices are then stopped and the lines that arrived saved, outside the handler.

#include <signal.h>

namespace clearway::cli {

// Installs the handlers for the life of the object and restores the previous ones after. One at
// a time.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  // Readable once a signal came.
  int descriptor() const;
  // "SIGINT" or "SIGTERM": the last signal that came.
  const char* lastSignalName() const;

 private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

}  // namespace clearway::cli
