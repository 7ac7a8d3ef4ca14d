#pragma once
// Scoped timers (as deal.II's TimerOutput::Scope): the wall time of a block added to one of the
// run's figures when the block ends, however it ends.
//
//   { ScopedTimer t(timings.solve); system.solve(b, x); }
#include <chrono>

namespace hencky {

using Clock = std::chrono::steady_clock;

/// Seconds from t0 to now.
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

class ScopedTimer {
 public:
  explicit ScopedTimer(double& total) : total_(total), t0_(Clock::now()) {}
  ~ScopedTimer() { total_ += seconds_since(t0_); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double& total_;
  Clock::time_point t0_;
};

}  // namespace hencky
