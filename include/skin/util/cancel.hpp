#pragma once
// Cooperative cancellation of long computations. The application requests it (from a SIGINT or
// SIGTERM handler: request() is async-signal-safe); the libraries' long loops (Monte Carlo
// batches, render tiles, texture-fit chunks, table nodes, validation cases, measured-spectra
// fits) poll it between units of work and end by throwing Cancelled, so that nothing half-done
// is returned and no output is written. A library never exits or prints; the application
// catches Cancelled, removes nothing (outputs are written only after the work) and exits.
// One flag per process: a signal concerns the whole process.
#include <stdexcept>

namespace skin::util {

class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

namespace cancel {
void request() noexcept;     // async-signal-safe
bool requested() noexcept;   // a relaxed atomic load: cheap enough for per-pixel polling
void reset() noexcept;       // for tests
// Throws Cancelled when cancellation was requested.
inline void check() {
  if (requested()) throw Cancelled();
}
}  // namespace cancel

}  // namespace skin::util
