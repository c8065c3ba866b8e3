// The targets' own models (export.hpp, docs/export.md): the albedo inversions and profile shapes
// as the targets implement them.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "skin/export/export.hpp"

namespace skin::exporting {

double burley_profile(double d, double r) {
  if (!(r > 0) || !(d > 0)) return 0.0;
  return (std::exp(-r / d) + std::exp(-r / (3.0 * d))) / (8.0 * std::numbers::pi * d * r);
}

double chiang_alpha(double A) {
  // Chiang, Kutz & Burley 2016, eq. 3 (a fit of the random walk's multiple-scattering albedo).
  A = std::clamp(A, 0.0, 1.0);
  const double s = 4.09712 + 4.20863 * A - std::sqrt(9.59217 + 41.6808 * A + 17.7126 * A * A);
  return 1.0 - s * s;
}

namespace {
// p(g) = sum c[i] g^i (Horner).
template <std::size_t N>
double poly(const double (&c)[N], double g) {
  double v = 0;
  for (std::size_t i = N; i-- > 0;) v = v * g + c[i];
  return v;
}
}  // namespace

double cycles_alpha(double A, double g) {
  // Cycles' subsurface_random_walk_remap (Blender 3.0+): a blend of two fits in atan(k A), each
  // coefficient a degree-7 polynomial in g (the values are Cycles'; Wrenninge, Villemin & Hery
  // 2017 give the method).
  static constexpr double cA[] = {1.8260523782, -1.28451056436, -1.79904629312, 9.19393289202,
                                  -22.8215585862, 32.0234874259, -23.6264803333, 7.21067002658};
  static constexpr double cB[] = {0.0, 31.1491581433, -201.847017512, 841.576016723,
                                  -2018.09288505, 2731.71560286, -1935.41424244, 559.009054474};
  static constexpr double cC[] = {1.09686102424, -0.394704063468, 1.05258115941, -8.83963712726,
                                  28.8643230661, -46.8802913581, 38.5402837518, -12.7181042538};
  static constexpr double cD[] = {0.496310210422, 0.360146581622, -2.15139309747, 17.8896899217,
                                  -55.2984010333, 82.065982243, -58.5106008578, 15.8478295021};
  static constexpr double cE[] = {0.0, 76.7316253952, -594.356773233, 2448.8834203,
                                  -5576.68528998, 7116.60171912, -4763.54467887, 1303.5318055};
  static constexpr double cF[] = {2.40602999408, -2.51814844609, 9.18494908356, -79.2191708682,
                                  259.082868209, -403.613804597, 302.85712436, -87.4370473567};
  A = std::clamp(A, 0.0, 1.0);
  const double a = poly(cA, g), b = 4.98511194385 + 0.127355959438 * std::exp(poly(cB, g));
  const double c = poly(cC, g), d = poly(cD, g);
  const double e = 4.23190299701 + 0.00310603949088 * std::exp(poly(cE, g)), f = poly(cF, g);
  const double blend = std::pow(A, 0.25);
  const double alpha = (1.0 - blend) * a * std::pow(std::atan(b * A), c) +
                       blend * d * std::pow(std::atan(e * A), f);
  return std::clamp(alpha, 0.0, 0.999999);
}

}  // namespace skin::exporting
