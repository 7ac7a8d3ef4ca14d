#include "core/interrupt.hpp"

#include <csignal>

namespace hencky {
namespace {
volatile std::sig_atomic_t requested = 0;
}

void request_interrupt() {
  requested = 1;
}
bool interrupt_requested() {
  return requested != 0;
}
void clear_interrupt() {
  requested = 0;
}

}  // namespace hencky
