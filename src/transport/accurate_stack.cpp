// AccurateStack: adding-doubling totals; profiles from the table of frequency-domain skin
// profiles or from radiative transfer in the spatial-frequency domain (docs/accurate-solver.md,
// sec. 3-5).
#include <ostream>

#include "skin/transport/accurate.hpp"
#include "skin/transport/skin_stack_table.hpp"

namespace skin::transport::accurate {

using skin::physics::LayerStack;

AccurateStack::AccurateStack(const LayerStack& stack, const Options& options)
    : AccurateStack(stack, options, Cache()) {}

AccurateStack::AccurateStack(const LayerStack& stack, const Options& options, const Cache& cache)
    : totals_(adding_doubling(stack, options, cache)) {
  if (reads_skin_table(stack)) {
    // The two-layer skin geometry: the frequency-domain profile, tabulated.
    skin_ = std::make_unique<SkinStackProfile>(SkinStackTable::builtin(), stack, totals_.R_d);
    return;
  }
  FrequencyProfileOptions o;
  o.transport.totals = options;
  frequency_ = std::make_unique<FrequencyStack>(stack, o, cache);
}

AccurateStack::~AccurateStack() = default;

bool AccurateStack::reads_skin_table(const LayerStack& stack) {
  return SkinStackTable::builtin().gap(stack).empty();
}

double AccurateStack::singular(double r) const {
  return skin_ ? (*skin_)(r) : frequency_->singular(r);
}

double AccurateStack::residual_k(double k) const {
  return skin_ ? 0.0 : frequency_->residual_k(k);  // the table's profile is all in space
}

std::ostream& operator<<(std::ostream& os, const AccurateStack& s) {
  return os << "AccurateStack{" << s.totals()
            << (s.skin_table() ? ", skin table" : ", frequency domain") << '}';
}

}  // namespace skin::transport::accurate
