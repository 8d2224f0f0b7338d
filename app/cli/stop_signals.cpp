#include "stop_signals.h"

#include <fcntl.h>
#include <unistd.h>

#include <csignal>
#include <stdexcept>

namespace clearway::cli {
namespace {

int stop_pipe[2] = {-1, -1};
volatile std::sig_atomic_t stop_signal = 0;

void onStopSignal(int signal_number) {
  stop_signal = signal_number;
  const char byte = 1;
  [[maybe_unused]] const ssize_t ignored = ::write(stop_pipe[1], &byte, 1);
}

}  // namespace

StopSignals::StopSignals() {
  if (::pipe2(stop_pipe, O_CLOEXEC | O_NONBLOCK) != 0)
    throw std::runtime_error("cannot create a pipe for the stop signals");
  stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGINT, &action, &previous_int_);
  ::sigaction(SIGTERM, &action, &previous_term_);
}

StopSignals::~StopSignals() {
  ::sigaction(SIGINT, &previous_int_, nullptr);
  ::sigaction(SIGTERM, &previous_term_, nullptr);
  ::close(stop_pipe[0]);
  ::close(stop_pipe[1]);
  stop_pipe[0] = stop_pipe[1] = -1;
}

int StopSignals::descriptor() const {
  return stop_pipe[0];
}

const char* StopSignals::lastSignalName() const {
  return stop_signal == SIGTERM ? "SIGTERM" : "SIGINT";
}

}  // namespace clearway::cli
