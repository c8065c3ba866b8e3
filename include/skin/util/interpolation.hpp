#pragma once
// Interpolation stencils on uniformly spaced nodes, in node units (node i at t = i). One home for
// every stencil of the project, each tested in tests/util/test_numerics.cpp.
#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace skin::util {

// Weights of N-point Lagrange interpolation through nodes 0, 1, ..., N - 1 evaluated at t:
// f(t) ~ sum_a w[a] f(a), w[a] = prod_{b != a} (t - b) / (a - b). Exact for polynomials of degree
// N - 1; the weights sum to 1. Intended for t in [0, N - 1] (the middle interval is the most
// accurate).
template <std::size_t N>
inline std::array<double, N> lagrange_weights(double t) {
  std::array<double, N> w;
  for (std::size_t a = 0; a < N; ++a) {
    w[a] = 1;
    for (std::size_t b = 0; b < N; ++b)
      if (b != a) w[a] *= (t - static_cast<double>(b)) / (static_cast<double>(a) - static_cast<double>(b));
  }
  return w;
}
inline std::array<double, 4> lagrange4_weights(double t) { return lagrange_weights<4>(t); }

// 4-point Lagrange interpolation among increasing, not necessarily even nodes (at least four):
// f(v) ~ sum_a weights[a] f(nodes[first + a]), the stencil centred on v's interval and moved
// inwards at the ends (extrapolating beyond them). Exact for cubics in the node coordinate.
struct Lagrange4Stencil {
  std::size_t first = 0;
  std::array<double, 4> weights{};
};
inline Lagrange4Stencil lagrange4_stencil(const std::vector<double>& nodes, double v) {
  const std::size_t n = nodes.size();
  const auto above = static_cast<std::size_t>(std::upper_bound(nodes.begin(), nodes.end(), v) - nodes.begin());
  const std::size_t i = above == 0 ? 0 : above - 1;  // nodes[i] <= v < nodes[i + 1]
  Lagrange4Stencil s;
  s.first = std::min(i > 0 ? i - 1 : 0, n - 4);
  for (std::size_t a = 0; a < 4; ++a) {
    s.weights[a] = 1;
    for (std::size_t b = 0; b < 4; ++b)
      if (b != a) s.weights[a] *= (v - nodes[s.first + b]) / (nodes[s.first + a] - nodes[s.first + b]);
  }
  return s;
}

// Catmull-Rom spline between p1 (t = 0) and p2 (t = 1), with neighbours p0 (t = -1) and p3
// (t = 2): the cubic Hermite interpolant with central-difference tangents (C1 across nodes;
// exact for quadratics, whose central differences are their derivatives; Catmull & Rom 1974).
inline double catmull_rom(double p0, double p1, double p2, double p3, double t) {
  return p1 + 0.5 * t * (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)));
}

// Index i and weight t of v among increasing nodes (at least two): v ~ (1 - t) nodes[i] +
// t nodes[i + 1], clamped to the end intervals (t in [0, 1]).
inline std::pair<std::size_t, double> locate(const std::vector<double>& nodes, double v) {
  if (v <= nodes.front()) return {0, 0.0};
  if (v >= nodes.back()) return {nodes.size() - 2, 1.0};
  const auto it = std::upper_bound(nodes.begin(), nodes.end(), v);
  const std::size_t i = static_cast<std::size_t>(it - nodes.begin()) - 1;
  return {i, (v - nodes[i]) / (nodes[i + 1] - nodes[i])};
}
}  // namespace skin::util
