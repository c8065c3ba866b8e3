// AccurateStack: adding-doubling totals, profiles from the transport tables of the top layer or
// from radiative transfer in the spatial-frequency domain (docs/accurate-solver.md, sec. 3, 5).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>

#include "skin/physics/fresnel.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/diffusion.hpp"
#include "skin/transport/skin_stack_table.hpp"

namespace skin::accurate {

namespace {

// The top layer alone, with the boundaries it has in the stack (the index below it is that of
// the next layer, or of the medium below).
LayerStack top_layer(const LayerStack& stack) {
  LayerStack top;
  top.layers = {stack.layers.front()};
  top.eta_above = stack.eta_above;
  top.eta_below = stack.layers.size() > 1 ? stack.layers[1].eta : stack.eta_below;
  return top;
}

// The built-in tables that describe the top layer of `stack`: its index and the index above it
// are theirs, its g is a table's or lies between two tables' (then blended, weight w on the
// upper one), and, for a finite layer, the index below it is matched and its thickness in range.
// `gap` says why not (empty when they do).
struct TableChoice {
  const TopLayerTable* lo = nullptr;
  const TopLayerTable* hi = nullptr;
  double w = 0;
  std::string gap;
};
std::string number(double v) {
  std::ostringstream os;
  os.precision(3);
  os << v;
  return os.str();
}
TableChoice tables_for(const LayerStack& stack) {
  const Layer& l0 = stack.layers.front();
  std::vector<const TopLayerTable*> same;
  for (const auto& t : TopLayerTable::builtin_set())
    if (std::abs(l0.eta - t.eta) < 1e-9 && std::abs(stack.eta_above - t.eta_above) < 1e-9)
      same.push_back(&t);
  TableChoice c;
  const auto& all = TopLayerTable::builtin_set();
  if (same.empty()) {
    c.gap = "top layer eta = " + number(l0.eta) + " under eta_above = " +
            number(stack.eta_above) + " has no transport table (tables: eta = " +
            number(all.front().eta) + " under " + number(all.front().eta_above) + ")";
    return c;
  }
  for (std::size_t i = 0; i < same.size(); ++i) {
    if (std::abs(l0.g - same[i]->g) < 1e-9) {
      c.lo = c.hi = same[i];
      break;
    }
    if (i + 1 < same.size() && l0.g > same[i]->g && l0.g < same[i + 1]->g &&
        same[i]->same_grid(*same[i + 1])) {
      c.lo = same[i];
      c.hi = same[i + 1];
      c.w = (l0.g - same[i]->g) / (same[i + 1]->g - same[i]->g);
      break;
    }
  }
  if (!c.lo) {
    c.gap = "top layer g = " + number(l0.g) + " is outside the transport tables' [" +
            number(same.front()->g) + ", " + number(same.back()->g) + "]";
    return c;
  }
  if (l0.semi_infinite()) return c;  // a half-space is split (constructor)
  // A finite top layer: only over a half-space (the skin geometry, any dermis scattering and
  // thickness the tables cover, so that skin stays fast) and only when it is at least as thick
  // as the skin table's thinnest epidermis, sigma_s' d = 0.59. A dark top 0.2 of that thick
  // over a bright layer (section 8, "dark over bright") was 44 % low at 0.15 mm: the diffusion
  // of the layer below is seen through it within a transport mean free path of the beam.
  const auto& ls = stack.layers;
  const double tau_min = SkinStackTable::builtin().tau.front();
  std::string why;
  if (ls.size() != 2 || !ls[1].semi_infinite())
    why = "it is not over a single half-space";
  else if (ls[1].eta != l0.eta || ls[1].g != l0.g)
    why = "the half-space's index or g is not the top layer's";
  else if (!(l0.sigma_s_prime * l0.thickness >= tau_min))
    why = "its sigma_s' d = " + number(l0.sigma_s_prime * l0.thickness) + " is below " + number(tau_min);
  if (!why.empty()) {
    c = {};
    c.gap = "the transport tables' finite top layer is used over a half-space of the same medium's "
            "index and g, at least " + number(tau_min) + " / sigma_s' thick, only (" + why + ")";
    return c;
  }
  const double sigma_t_prime = l0.sigma_a + l0.sigma_s_prime;
  const double n_below = stack.layers.size() > 1 ? stack.layers[1].eta : stack.eta_below;
  const double tau_prime = l0.thickness * sigma_t_prime;
  if (std::abs(n_below - l0.eta) >= 1e-9) {
    c = {};
    c.gap = "index step below the top layer (" + number(l0.eta) + " over " + number(n_below) +
            "): the transport tables assume a matched one";
  } else if (!c.lo->covers(l0.sigma_s_prime / sigma_t_prime, tau_prime)) {
    c = {};
    c.gap = "top layer is " + number(tau_prime) +
            " transport mean free paths thick, outside the transport tables' " +
            number(all.front().tau.front()) + "-" + number(all.front().tau.back());
  }
  return c;
}
}  // namespace

std::string transport_table_gap(const LayerStack& stack) {
  stack.validate();
  const TableChoice c = tables_for(stack);
  if (!c.gap.empty()) return c.gap;
  // Darker than the darkest node: the table is clamped there (its R_e then exceeds the
  // adding-doubling reflectance of the layer, 3x at alpha' = 0.04: c_top carries the difference).
  const Layer& l0 = stack.layers.front();
  const double alpha_prime = l0.sigma_s_prime / (l0.sigma_a + l0.sigma_s_prime);
  const double x_max = c.lo->x.back();
  const double alpha_min = 1.0 - x_max * x_max;
  if (alpha_prime < alpha_min)
    return "top layer's reduced albedo alpha' = " + number(alpha_prime) +
           " is below the transport tables' " + number(alpha_min) +
           "; the profile's shape is their darkest node's, scaled to the total, not validated "
           "against Monte Carlo";
  return {};
}

AccurateStack::AccurateStack(const LayerStack& stack, const Options& options)
    : AccurateStack(stack, options, Cache()) {}

AccurateStack::AccurateStack(const LayerStack& stack, const Options& options, const Cache& cache)
    : totals_(adding_doubling(stack, options, cache)) {
  const auto& ls = stack.layers;
  const Layer& l0 = ls.front();
  if (const SkinStackTable& skin = SkinStackTable::builtin(); skin.gap(stack).empty()) {
    // The two-layer skin geometry: the frequency-domain profile, tabulated.
    skin_ = std::make_unique<SkinStackProfile>(skin, stack, totals_.R_d);
    return;
  }
  if (!transport_table_gap(stack).empty()) {
    // Outside the tables: radiative transfer in the spatial-frequency domain.
    FrequencyProfileOptions o;
    o.transport.totals = options;
    frequency_ = std::make_unique<FrequencyStack>(stack, o, cache);
    return;
  }
  if (ls.size() > 1) {
    LayerStack rest;
    rest.layers.assign(ls.begin() + 1, ls.end());
    rest.eta_above = l0.eta;
    rest.eta_below = stack.eta_below;
    rest_.emplace(rest);
  }
  const TableChoice choice = tables_for(stack);
  table_ = choice.lo;
  {
    // Transport top layer (accurate.hpp): R_e in space, the light from below in k.
    sigma_t_prime_ = l0.sigma_a + l0.sigma_s_prime;
    LayerStack top = top_layer(stack);
    if (l0.semi_infinite()) {
      // A half-space is split at the table's thickest layer (32 transport mean free paths): the
      // transport slab on top, the same medium below it by diffusion (accurate that deep).
      top.layers.front().thickness = table_->tau.back() / sigma_t_prime_;
      top.eta_below = l0.eta;
      LayerStack rest;
      rest.layers = {l0};
      rest.eta_above = l0.eta;
      rest_.emplace(rest);
    }
    const double tau_prime = top.layers.front().thickness * sigma_t_prime_;
    const double alpha_prime = l0.sigma_s_prime / sigma_t_prime_;
    top_sample_ = table_->sample(alpha_prime, tau_prime);
    if (choice.hi != choice.lo)
      top_sample_ = TopLayerTable::blend(top_sample_, choice.hi->sample(alpha_prime, tau_prime),
                                         choice.w);
    const double R_top_ad = rest_ ? adding_doubling(top, options, cache).R_d : totals_.R_d;
    const double R_e = table_->R_e_integral(top_sample_);
    const double deep = coupling_k(0.0);
    c_top_ = R_e > 0 ? R_top_ad / R_e : 1.0;
    const double deep_ad = totals_.R_d - R_top_ad;
    // The light from below is the adding-doubling share of the total when that share is resolved
    // (more than 0.1 % of the total). In the darkest skin (african, below 650 nm) almost
    // nothing comes back from the dermis and the share is not resolved by the difference of two
    // totals: the transport coupling is kept as it is (its epidermis is Monte Carlo transport;
    // c_deep is 0.95-1.3 where resolved).
    if (rest_ && deep > 0 && deep_ad > 1e-3 * totals_.R_d && deep_ad > 0.1 * deep) {
      c_deep_ = deep_ad / deep;
    } else {
      c_deep_ = rest_ && deep > 0 ? 1.0 : 0.0;
      c_top_ = R_e > 0 ? (totals_.R_d - c_deep_ * deep) / R_e : 1.0;
      if (c_top_ <= 0 && deep > 0) {
        // The coupling alone would exceed the total (a stack far from skin): give the light from
        // below its adding-doubling share, or none, so that both parts stay positive.
        c_deep_ = std::max(0.0, deep_ad) / deep;
        c_top_ = R_e > 0 ? (totals_.R_d - c_deep_ * deep) / R_e : 1.0;
      }
    }
  }
}

AccurateStack::~AccurateStack() = default;

double AccurateStack::coupling_k(double k) const {
  if (!rest_) return 0.0;
  const double kappa = k / sigma_t_prime_;
  const auto [T_down, T_up, R_up] = table_->transforms_at(top_sample_, kappa);
  const double R_below = rest_->R_k(k);
  return T_down * R_below * T_up / (1.0 - R_up * R_below);
}

double AccurateStack::singular(double r) const {
  if (skin_) return (*skin_)(r);
  if (frequency_) return frequency_->singular(r);
  return c_top_ * sigma_t_prime_ * sigma_t_prime_ * table_->R_e_at(top_sample_, r * sigma_t_prime_);
}

double AccurateStack::residual_k(double k) const {
  if (skin_) return 0.0;  // all in space
  if (frequency_) return frequency_->residual_k(k);
  return c_deep_ * coupling_k(k);
}

std::ostream& operator<<(std::ostream& os, const AccurateStack& s) {
  return os << "AccurateStack{" << s.totals()
            << (s.skin_table() ? ", skin table" : s.transport_top() ? ", transport top layer" : ", frequency domain")
            << ", c_top=" << s.c_top()
            << ", c_deep=" << s.c_deep() << '}';
}

}  // namespace skin::accurate
