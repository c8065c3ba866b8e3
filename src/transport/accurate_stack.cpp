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
    auto read = [&h](const physics::Layer& l, double R_d) {
      return std::make_unique<SkinStackProfile>(h.x, h.ln_rho_at(l.sigma_a / l.sigma_s_prime, l.g, l.eta), l.sigma_s_prime,
                                                R_d);
    };
    top_as_half_space_ = stack.layers.size() > 1;
    half_space_table_ = true;
    if (nearly_hides_below(stack)) {
      // The top layer nearly hides the lower one: the top layer's half-space with its own total,
      // and the rest of the stack's total spread as the lower layer's half-space.
      LayerStack top;
      top.eta_above = stack.eta_above;
      top.layers = {t};
      top.layers.front().thickness = physics::kInfinity;
      const double R_top = adding_doubling(top, options, cache).R_d, below = totals_.R_d - R_top;
      if (below > 0) {
        skin_ = read(t, R_top);
        below_ = read(stack.layers.back(), below);
        return;
      }
    }
    skin_ = read(t, totals_.R_d);
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

double AccurateStack::top_layer_efolds(const LayerStack& stack) {
  if (stack.layers.size() < 2) return 0;
  const physics::Layer& t = stack.layers.front();
  if (t.semi_infinite() || !(t.thickness > 0) || !(t.sigma_a >= 0) || !(t.sigma_s_prime >= 0)) return 0;
  const double straight = (t.sigma_s_prime + t.sigma_a) * t.thickness;
  const double diffusive = std::sqrt(3.0 * t.sigma_a * (t.sigma_s_prime + t.sigma_a)) * t.thickness;
  return std::min(straight, diffusive);
}

bool AccurateStack::hides_below(const LayerStack& stack) { return top_layer_efolds(stack) >= kHiddenBelowEfolds; }

bool AccurateStack::nearly_hides_below(const LayerStack& stack) {
  if (stack.layers.size() != 2 || !stack.layers.back().semi_infinite()) return false;
  const double n = top_layer_efolds(stack);
  return n >= kNearlyHiddenEfolds && n < kHiddenBelowEfolds;
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
  if (!skin_) return frequency_->singular(r);
  return below_ ? (*skin_)(r) + (*below_)(r) : (*skin_)(r);
}

double AccurateStack::residual_k(double k) const {
  return skin_ ? 0.0 : frequency_->residual_k(k);  // the table's profile is all in space
}

std::ostream& operator<<(std::ostream& os, const AccurateStack& s) {
  return os << "AccurateStack{" << s.totals()
            << (s.half_space_table() ? (s.below_as_half_space() ? ", half-space table, top and lower layer as half-spaces"
                                        : s.top_as_half_space() ? ", half-space table, top as half-space"
                                                                : ", half-space table")
            : s.skin_table()     ? ", skin table"
            : s.top_as_half_space() ? ", frequency domain, top as half-space"
                                    : ", frequency domain") << '}';
}

}  // namespace skin::transport::accurate
