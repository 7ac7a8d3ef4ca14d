#pragma once
// A request to stop the run, from the command line's SIGINT/SIGTERM handler (app/run.cpp): the
// step loop and the heat analysis look at it between iterations, stop, and keep every step that
// converged (exit status 4, docs/cli.md).
#include <stdexcept>

namespace hencky {

/// Async-signal-safe: sets the flag (a lock-free atomic). Returns whether it was set already:
/// of two signals handled at once by two threads, exactly one sees false.
bool request_interrupt();
bool interrupt_requested();
/// Clears the flag (tests).
void clear_interrupt();

/// Thrown where an iteration sees the request; the step loop turns it into its status.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace hencky
