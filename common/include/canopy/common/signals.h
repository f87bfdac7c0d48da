// The signals after which canopy removes what it was writing (atomic outputs, detect's
// temporary directory), and a guard that holds them back while a rename or swap completes.
#pragma once

#include <pthread.h>

#include <csignal>

namespace canopy::common {

inline constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ};

// Blocks kCleanupSignals for its lifetime; one that arrives meanwhile is delivered at its end.
class HoldSignals {
 public:
  HoldSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int sig : kCleanupSignals) sigaddset(&set, sig);
    pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~HoldSignals() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  HoldSignals(const HoldSignals&) = delete;
  HoldSignals& operator=(const HoldSignals&) = delete;

 private:
  sigset_t old_;
};

}  // namespace canopy::common
