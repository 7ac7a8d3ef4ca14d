#include "core/interrupt.hpp"

#include <atomic>

namespace hencky {
namespace {
// A signal sent to the process may be handled by any of its threads (OpenMP's), two pending
// ones by two threads at once: the test-and-set must be one atomic step.
std::atomic<bool> requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");
}  // namespace

bool request_interrupt() {
  return requested.exchange(true);
}
bool interrupt_requested() {
  return requested.load();
}
void clear_interrupt() {
  requested.store(false);
}

}  // namespace hencky
