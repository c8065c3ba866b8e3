// AccurateStack: diffusion shapes with adding-doubling totals (docs/accurate-solver.md, sec. 3).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>

#include "skin/physics/fresnel.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/diffusion.hpp"

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

// Sums over the pole family c + i P (all integers i) of exp(-|c + i P| s), with and without the
// sign of the depth: the 2D transforms of the fluence (e^{-s_tr d} / d -> 2 pi e^{-|z| s} / s) and
// of the flux (z (1 + s_tr d) e^{-s_tr d} / d^3 -> 2 pi sgn(z) e^{-|z| s}) of each pole.
struct PoleSums {
  double plain = 0, signed_ = 0;
};
// q = 1 / (1 - exp(-P s)), shared by the two families of a slab (0 for P = infinity: no images).
PoleSums pole_sums(double c, double P, double q, double s) {
  if (!std::isfinite(P)) {
    const double e = std::exp(-std::abs(c) * s);
    return {e, c >= 0 ? e : -e};
  }
  const double c0 = c - P * std::floor(c / P);  // in [0, P)
  const double up = std::exp(-c0 * s) * q, down = std::exp(-(P - c0) * s) * q;
  return {up + down, up - down};
}

// Partial current leaving the surface z = z_s of a slab: C_phi phi + C_j j, from the real poles
// z_r + i 2L and the images -z_r - 2 z_b_top + i 2L (DJ05 eq 7), fluence phi = alpha' / (4 pi D)
// sum(+-e^{-s_tr d} / d), flux j = alpha' / (4 pi) sum(+-z (1 + s_tr d) e^{-s_tr d} / d^3).
double partial_current_k(const DiffusionSlab& sl, double z_s, double C_phi, double C_j, double k,
                         bool nearest_pair_only) {
  const double s = std::sqrt(sl.sigma_tr * sl.sigma_tr + k * k);
  const double P = nearest_pair_only || sl.semi_infinite() ? kInfinity : 2.0 * sl.L;
  const double q = std::isfinite(P) ? 1.0 / (1.0 - std::exp(-P * s)) : 0.0;
  // Depths of the poles below the surface z_s (the surface z = d counts depth d - z).
  const double sign = z_s == 0.0 ? 1.0 : -1.0;
  const PoleSums real = pole_sums(sign * (sl.z_r - z_s), P, q, s);
  const PoleSums image = pole_sums(sign * (-sl.z_r - 2.0 * sl.z_b_top - z_s), P, q, s);
  const double phi = sl.alpha_prime / (2.0 * sl.D * s) * (real.plain - image.plain);
  const double j = 0.5 * sl.alpha_prime * (real.signed_ - image.signed_);
  return C_phi * phi + C_j * j;
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

FresnelMoments FresnelMoments::of(double eta) {
  FresnelMoments m;
  if (eta == 1.0) return m;
  constexpr int n = 4000;
  for (int i = 0; i < n; ++i) {
    const double mu = (i + 0.5) / n;
    const double F = fresnel_dielectric(mu, eta, 1.0);
    m.C1 += F * mu / n;
    m.C2 += F * mu * mu / n;
  }
  return m;
}

std::string transport_table_gap(const LayerStack& stack) {
  stack.validate();
  const TableChoice c = tables_for(stack);
  if (!c.gap.empty())
    return c.gap + "; the profile's shape falls back to corrected diffusion, not validated "
                   "against Monte Carlo (it can be several times off)";
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
    : AccurateStack(stack, options, [&] {
        stack.validate();
        return FresnelMoments::of(stack.layers.front().eta / stack.eta_above);
      }(), Cache()) {}

AccurateStack::AccurateStack(const LayerStack& stack, const Options& options,
                             const FresnelMoments& fm, const Cache& cache)
    : totals_(adding_doubling(stack, options, cache)) {
  const auto& ls = stack.layers;
  const Layer& l0 = ls.front();
  const double eta_top = l0.eta / stack.eta_above;
  // Partial current through the top surface (Kienle & Patterson 1997): the diffuse radiance
  // phi / 4 pi + 3 j mu / 4 pi, times 1 - F(mu), integrated over the outgoing hemisphere.
  C_phi_ = 0.25 * (1.0 - 2.0 * fm.C1);
  C_j_ = 0.5 * (1.0 - 3.0 * fm.C2);
  const double A_top = eta_top == 1.0 ? 1.0 : (1.0 + 3.0 * fm.C2) / (1.0 - 2.0 * fm.C1);
  const double n_below = ls.size() > 1 ? ls[1].eta : stack.eta_below;
  const double A_bottom = A_boundary(l0.eta / n_below);
  top_ = DiffusionSlab::make(l0.sigma_a, l0.sigma_s_prime, l0.thickness, A_top, A_bottom);
  if (!top_.semi_infinite()) top_up_ = top_.flipped();
  if (ls.size() > 1) {
    LayerStack rest;
    rest.layers.assign(ls.begin() + 1, ls.end());
    rest.eta_above = l0.eta;
    rest.eta_below = stack.eta_below;
    rest_.emplace(rest);
  }
  const TableChoice choice = tables_for(stack);
  if ((table_ = choice.lo)) {
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
    return;
  }
  const double R_mp = diffusion_R_k(0.0);
  const double R_top_mp = diffusion_top_R_k(0.0);
  if (!rest_) {
    c_top_ = c_deep_ = totals_.R_d / R_mp;
    if (!(c_top_ > 0 && std::isfinite(c_top_))) use_dipole_only();
    return;
  }
  const double R_top_ad = adding_doubling(top_layer(stack), options, cache).R_d;
  const double deep_mp = R_mp - R_top_mp;
  c_top_ = R_top_ad / R_top_mp;
  // The light that came back from below the top layer: its adding-doubling share is the rest of
  // the total. If diffusion sees (almost) none, the whole correction goes to the top layer.
  const double deep_ad = totals_.R_d - R_top_ad;
  if (deep_mp > 1e-9 * R_mp && deep_ad >= 0) {
    c_deep_ = deep_ad / deep_mp;
  } else {
    c_deep_ = 1;
    c_top_ = (totals_.R_d - deep_mp) / R_top_mp;
  }
  if (!(c_top_ > 0 && c_deep_ >= 0 && std::isfinite(c_top_) && std::isfinite(c_deep_))) {
    // A top layer much thinner than a transport mean free path (below the tables' range) puts
    // diffusion's source z_r below it, and its diffusion reflectance or the rest can turn
    // negative: then the whole stack's diffusion shape, scaled to the total, or, where that is
    // not positive either, the light from below alone.
    if (R_mp > 0) {
      c_top_ = c_deep_ = totals_.R_d / R_mp;
    } else {
      use_dipole_only();
    }
  }
}

void AccurateStack::use_dipole_only() {
  // The last resort of the diffusion shape: the top layer's nearest image pair alone (always
  // positive), scaled to the total.
  dipole_only_ = true;
  c_deep_ = 0;
  const double dipole = top_dipole_k(0.0);
  c_top_ = dipole > 0 ? totals_.R_d / dipole : 0.0;
}

double AccurateStack::coupling_k(double k) const {
  if (!rest_) return 0.0;
  const double kappa = k / sigma_t_prime_;
  const auto [T_down, T_up, R_up] = table_->transforms_at(top_sample_, kappa);
  const double R_below = rest_->R_k(k);
  return T_down * R_below * T_up / (1.0 - R_up * R_below);
}

double AccurateStack::diffusion_top_R_k(double k) const {
  return partial_current_k(top_, 0.0, C_phi_, C_j_, k, false);
}

double AccurateStack::top_dipole_k(double k) const {
  return partial_current_k(top_, 0.0, C_phi_, C_j_, k, true);
}

double AccurateStack::diffusion_R_k(double k) const {
  return diffusion_R_k_given_top(k, diffusion_top_R_k(k));
}

double AccurateStack::diffusion_R_k_given_top(double k, double R1) const {
  if (!rest_) return R1;
  // DJ05 adding with the top layer's own transfer inside the stack (flux j), except where light
  // leaves through the top surface: there the partial current. Seen from below, the top surface
  // is the slab's bottom, z = d of the flipped slab.
  const double T1_down = top_.T_k(k);
  const double R1_up = top_up_.R_k(k);
  const double T1_up = partial_current_k(top_up_, top_up_.d, C_phi_, C_j_, k, false);
  const double R2 = rest_->R_k(k);
  return R1 + T1_down * R2 * T1_up / (1.0 - R1_up * R2);
}

double AccurateStack::singular(double r) const {
  if (table_)
    return c_top_ * sigma_t_prime_ * sigma_t_prime_ *
           table_->R_e_at(top_sample_, r * sigma_t_prime_);
  // The nearest image pair of the top layer in space: fluence and flux of a dipole.
  const double z_v = top_.z_r + 2.0 * top_.z_b_top;
  const double d_r = std::sqrt(r * r + top_.z_r * top_.z_r), d_v = std::sqrt(r * r + z_v * z_v);
  const double e_r = std::exp(-top_.sigma_tr * d_r), e_v = std::exp(-top_.sigma_tr * d_v);
  const double phi = top_.alpha_prime / (4.0 * std::numbers::pi * top_.D) * (e_r / d_r - e_v / d_v);
  const double j = top_.alpha_prime / (4.0 * std::numbers::pi) *
                   (top_.z_r * (1.0 + top_.sigma_tr * d_r) * e_r / (d_r * d_r * d_r) +
                    z_v * (1.0 + top_.sigma_tr * d_v) * e_v / (d_v * d_v * d_v));
  return c_top_ * (C_phi_ * phi + C_j_ * j);
}

double AccurateStack::residual_k(double k) const {
  if (table_) return c_deep_ * coupling_k(k);
  if (dipole_only_) return 0.0;
  const double R_top = diffusion_top_R_k(k);
  const double deep = rest_ ? diffusion_R_k_given_top(k, R_top) - R_top : 0.0;
  return c_top_ * (R_top - top_dipole_k(k)) + c_deep_ * deep;
}

std::ostream& operator<<(std::ostream& os, const AccurateStack& s) {
  return os << "AccurateStack{" << s.totals()
            << (s.transport_top() ? ", transport top layer" : ", diffusion shape")
            << ", c_top=" << s.c_top()
            << ", c_deep=" << s.c_deep() << '}';
}

}  // namespace skin::accurate
