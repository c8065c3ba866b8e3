// AccurateStack: adding-doubling totals; profiles from the table of frequency-domain skin
// profiles or from radiative transfer in the spatial-frequency domain (docs/accurate-solver.md,
// sec. 3-5).
#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/transport/accurate.hpp"
#include "skin/transport/half_space_table.hpp"
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
  if (reads_half_space_table(stack)) {
    // A lone half-space, or a top layer that hides the rest, of the skin domain's media: read.
    const physics::Layer& t = stack.layers.front();
    const HalfSpaceTable& h = HalfSpaceTable::builtin();
    skin_ = std::make_unique<SkinStackProfile>(h.x, h.ln_rho_at(t.sigma_a / t.sigma_s_prime, t.g, t.eta), t.sigma_s_prime,
                                               totals_.R_d);
    top_as_half_space_ = stack.layers.size() > 1;
    half_space_table_ = true;
    return;
  }
  FrequencyProfileOptions o;
  o.transport.totals = options;
  if (hides_below(stack)) {
    // Nothing that reaches below the top layer comes back measurably: its half-space.
    LayerStack top;
    top.eta_above = stack.eta_above;
    top.layers = {stack.layers.front()};
    top.layers.front().thickness = physics::kInfinity;
    frequency_ = std::make_unique<FrequencyStack>(top, o, cache);
    top_as_half_space_ = true;
    return;
  }
  frequency_ = std::make_unique<FrequencyStack>(stack, o, cache);
}

bool AccurateStack::hides_below(const LayerStack& stack) {
  if (stack.layers.size() < 2) return false;
  const physics::Layer& t = stack.layers.front();
  if (t.semi_infinite() || !(t.thickness > 0) || !(t.sigma_a >= 0) || !(t.sigma_s_prime >= 0)) return false;
  const double straight = (t.sigma_s_prime + t.sigma_a) * t.thickness;
  const double diffusive = std::sqrt(3.0 * t.sigma_a * (t.sigma_s_prime + t.sigma_a)) * t.thickness;
  return std::min(straight, diffusive) >= kHiddenBelowEfolds;
}

AccurateStack::~AccurateStack() = default;

bool AccurateStack::reads_skin_table(const LayerStack& stack) {
  return SkinStackTable::builtin().gap(stack).empty();
}

bool AccurateStack::reads_half_space_table(const LayerStack& stack) {
  return HalfSpaceTable::builtin().gap(stack).empty();
}

bool AccurateStack::reads_table(const LayerStack& stack) { return reads_skin_table(stack) || reads_half_space_table(stack); }

double AccurateStack::singular(double r) const {
  return skin_ ? (*skin_)(r) : frequency_->singular(r);
}

double AccurateStack::residual_k(double k) const {
  return skin_ ? 0.0 : frequency_->residual_k(k);  // the table's profile is all in space
}

std::ostream& operator<<(std::ostream& os, const AccurateStack& s) {
  return os << "AccurateStack{" << s.totals()
            << (s.half_space_table() ? (s.top_as_half_space() ? ", half-space table, top as half-space" : ", half-space table")
            : s.skin_table()     ? ", skin table"
            : s.top_as_half_space() ? ", frequency domain, top as half-space"
                                    : ", frequency domain") << '}';
}

}  // namespace skin::transport::accurate
