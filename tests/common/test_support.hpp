#pragma once
// Reference numerics shared by the test suites (the test targets link skin_test_support):
// Chandrasekhar's H-function by brute force, the chi-square tests of samplers, which cases a
// test runs under the sanitizers, and the two-layer stack of the skin table's reduced units.
#include <boost/math/distributions/chi_squared.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <vector>

#include "skin/physics/layer.hpp"
#include "skin/util/quadrature.hpp"

namespace skin::test {

// True in a build under AddressSanitizer (SKIN_SANITIZE; clang's __has_feature or GCC's macro).
// Tests that repeat one check over many cases run the first of them only there (`sanitized()`):
// that run is for memory errors and undefined behaviour, and each frequency-domain solve costs
// ~15x its Release time under the sanitizers; the Release suite runs every case.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kUnderSanitizers = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kUnderSanitizers = true;
#else
inline constexpr bool kUnderSanitizers = false;
#endif
#else
inline constexpr bool kUnderSanitizers = false;
#endif

// The cases a test runs: all of them, or the first under the sanitizers.
template <class T>
std::vector<T> sanitized(std::initializer_list<T> cases) {
  std::vector<T> v(cases);
  if (kUnderSanitizers && v.size() > 1) v.resize(1);
  return v;
}

// Chandrasekhar's H-function for isotropic scattering with single-scattering albedo omega in
// [0, 1): a semi-infinite, isotropically scattering, index-matched medium lit by a normal beam
// reflects 1 - H(1) sqrt(1 - omega) (the plane albedo; Chandrasekhar 1960, "Radiative Transfer",
// ch. V). Computed by iterating 1/H(mu) = sqrt(1 - omega) + (omega / 2) int_0^1 mu' H(mu') /
// (mu + mu') dmu' on `nodes` Gauss-Legendre points in [0, 1] (the form that converges also for
// omega -> 1); 200 nodes and 2000 sweeps give H(1) to better than 1e-10 for omega <= 0.99.
inline double chandrasekhar_H(double omega, double mu, int nodes = 200) {
  const util::QuadratureRule& rule = util::gauss_legendre(nodes);
  const std::size_t n = rule.x.size();
  std::vector<double> x(n), w(n), H(n, 1.0), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = 0.5 * (rule.x[i] + 1);
    w[i] = 0.5 * rule.w[i];
  }
  auto inverse = [&](double m) {
    double s = 0;
    for (std::size_t j = 0; j < n; ++j) s += w[j] * x[j] * H[j] / (m + x[j]);
    return std::sqrt(1 - omega) + 0.5 * omega * s;
  };
  for (int it = 0; it < 2000; ++it) {
    for (std::size_t i = 0; i < n; ++i) next[i] = 1.0 / inverse(x[i]);
    H.swap(next);
  }
  return 1.0 / inverse(mu);
}

// Pearson's chi-square statistic of n samples in `bins` equiprobable bins, each sample given by
// its CDF value u in [0, 1) (next_u() draws one).
template <class NextU>
double chi_square_equiprobable(std::size_t n, std::size_t bins, NextU next_u) {
  std::vector<double> count(bins, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = next_u();
    const auto b = std::min(bins - 1, static_cast<std::size_t>(u * static_cast<double>(bins)));
    count[b] += 1;
  }
  const double expected = static_cast<double>(n) / static_cast<double>(bins);
  double chi2 = 0;
  for (double c : count) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

// Pearson's chi-square test of observed counts against expected probabilities (n samples in
// all). Bins expected to hold fewer than 5 samples are pooled (the chi-square approximation needs
// that). Returns the p-value; tests reject below 1e-3 (with fixed seeds, so never flaky).
inline double chi_square_p(const std::vector<double>& observed, const std::vector<double>& probability,
                           double n) {
  double stat = 0, pooled_o = 0, pooled_e = 0;
  int dof = -1;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const double e = probability[i] * n;
    if (e < 5) {
      pooled_o += observed[i];
      pooled_e += e;
      continue;
    }
    stat += (observed[i] - e) * (observed[i] - e) / e;
    ++dof;
  }
  if (pooled_e >= 5) {
    stat += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
    ++dof;
  } else if (pooled_o > 10) {
    return 0.0;  // samples where the pdf says there should be (almost) none
  }
  if (dof < 1) return 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(dof), stat));
}

// A two-layer stack in the skin table's reduced units: the top layer's sigma_s' s [1/mm], tau = s d,
// a_e and a_d over s, g, index and the lower layer's sigma_s' over the top's.
inline physics::LayerStack reduced_stack(double s, double tau, double a_e, double a_d, double g, double eta,
                                         double ratio) {
  physics::LayerStack st;
  st.layers = {{a_e * s, s, tau / s, eta, g}, {a_d * s, ratio * s, physics::kInfinity, eta, g}};
  return st;
}

}  // namespace skin::test
