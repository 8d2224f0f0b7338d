#pragma once

// A full disk without root or a mount: while a FileSizeLimit lives, no file this process (or a
// child it starts) writes can grow beyond `bytes`. write(2) then fails with EFBIG ("File too
// large") as it fails with ENOSPC on a full disk; SIGXFSZ is ignored, so the write fails instead of
// killing the process. Lifted, writes succeed again, as on a disk where space was made.

#include <sys/resource.h>

#include <csignal>

namespace clearway::test {

class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    ::getrlimit(RLIMIT_FSIZE, &previous_);
    rlimit limit = previous_;
    limit.rlim_cur = bytes;
    ok_ = ::setrlimit(RLIMIT_FSIZE, &limit) == 0;
  }
  ~FileSizeLimit() { lift(); }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

  bool ok() const { return ok_; }  // the limit is in force
  void lift() {
    if (lifted_) return;
    lifted_ = true;
    ::setrlimit(RLIMIT_FSIZE, &previous_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit previous_{};
  void (*previous_handler_)(int) = SIG_DFL;
  bool ok_ = false;
  bool lifted_ = false;
};

}  // namespace clearway::test
