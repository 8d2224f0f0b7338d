#pragma once

// Progress reporting and cancellation for long core work, without Qt: a callback receives the
// fraction done in [0, 1] and returns false to ask the work to stop. A null callback never cancels.

#include <functional>
#include <stdexcept>

namespace clearway {

using ProgressCallback = std::function<bool(double fraction)>;

// Thrown by core work when its progress callback asked it to stop.
class OperationCancelled : public std::runtime_error {
 public:
  OperationCancelled() : std::runtime_error("cancelled") {}
};

// Reports `fraction` and throws OperationCancelled if the callback says stop.
inline void reportProgress(const ProgressCallback& progress, double fraction) {
  if (progress && !progress(fraction)) throw OperationCancelled();
}

}  // namespace clearway
