#include "skin/render/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/util/error.hpp"

namespace skin::render {

using skin::util::Pcg32;
using skin::util::mix64;

std::ostream& operator<<(std::ostream& os, const Vec3& v) {
  return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}

Vec2 sample_concentric_disk(Vec2 u) {
  const double a = 2 * u.x - 1, b = 2 * u.y - 1;
  if (a == 0 && b == 0) return {0, 0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4) * (b / a);
  } else {
    r = b;
    phi = kPi / 2 - (kPi / 4) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

Vec3 sample_cosine_hemisphere(Vec2 u) {
  const Vec2 d = sample_concentric_disk(u);
  return {d.x, d.y, std::sqrt(std::max(0.0, 1 - d.x * d.x - d.y * d.y))};
}
double pdf_cosine_hemisphere(double cos_theta) { return cos_theta > 0 ? cos_theta / kPi : 0.0; }

Vec3 sample_uniform_sphere(Vec2 u) {
  const double z = 1 - 2 * u.x;
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  const double phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 sample_uniform_cone(Vec2 u, double cos_theta_max) {
  const double c = 1 - u.x * (1 - cos_theta_max);
  const double s = std::sqrt(std::max(0.0, 1 - c * c));
  const double phi = 2 * kPi * u.y;
  return {s * std::cos(phi), s * std::sin(phi), c};
}
double pdf_uniform_cone(double cos_theta_max) { return 1.0 / (2 * kPi * (1 - cos_theta_max)); }

Distribution1D::Distribution1D(std::vector<double> weights) : w_(std::move(weights)) {
  SKIN_ASSERT(!w_.empty(), "Distribution1D needs at least one bin");
  cdf_.assign(w_.size() + 1, 0.0);
  for (std::size_t i = 0; i < w_.size(); ++i) {
    SKIN_ASSERT(w_[i] >= 0 && std::isfinite(w_[i]), "Distribution1D weight must be finite, >= 0");
    cdf_[i + 1] = cdf_[i] + w_[i];
  }
  const double sum = cdf_.back();
  const double n = static_cast<double>(w_.size());
  total_ = sum / n;
  if (sum == 0) {  // nothing to prefer: uniform
    for (std::size_t i = 0; i <= w_.size(); ++i) cdf_[i] = static_cast<double>(i) / n;
  } else {
    for (auto& c : cdf_) c /= sum;
  }
}

double Distribution1D::sample(double u, double* pdf, std::size_t* bin) const {
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, it - cdf_.begin() - 1));
  i = std::min(i, w_.size() - 1);
  while (cdf_[i + 1] - cdf_[i] <= 0 && i + 1 < w_.size()) ++i;  // skip empty bins
  const double n = static_cast<double>(w_.size());
  const double width = cdf_[i + 1] - cdf_[i];
  const double du = width > 0 ? (u - cdf_[i]) / width : 0.5;
  if (pdf) *pdf = width * n;
  if (bin) *bin = i;
  return std::min((static_cast<double>(i) + std::clamp(du, 0.0, 1.0)) / n, std::nextafter(1.0, 0.0));
}

double Distribution1D::pdf(double x) const {
  if (x < 0 || x >= 1) return 0.0;
  const auto i = std::min(static_cast<std::size_t>(x * static_cast<double>(w_.size())), w_.size() - 1);
  return (cdf_[i + 1] - cdf_[i]) * static_cast<double>(w_.size());
}

double Distribution1D::invert(double x) const {
  const double n = static_cast<double>(w_.size());
  const auto i = std::min(static_cast<std::size_t>(std::clamp(x, 0.0, 1.0) * n), w_.size() - 1);
  const double frac = x * n - static_cast<double>(i);
  return cdf_[i] + frac * (cdf_[i + 1] - cdf_[i]);
}

Distribution2D::Distribution2D(const std::vector<double>& weights, std::size_t nu, std::size_t nv) {
  SKIN_ASSERT(weights.size() == nu * nv && nu > 0 && nv > 0, "Distribution2D size mismatch");
  std::vector<double> row_totals(nv);
  conditional_.reserve(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    conditional_.emplace_back(std::vector<double>(weights.begin() + static_cast<std::ptrdiff_t>(v * nu),
                                                  weights.begin() + static_cast<std::ptrdiff_t>((v + 1) * nu)));
    row_totals[v] = conditional_.back().total();
  }
  marginal_ = Distribution1D(std::move(row_totals));
}

Vec2 Distribution2D::sample(Vec2 u, double* pdf) const {
  double pv = 0, pu = 0;
  std::size_t row = 0;
  const double v = marginal_.sample(u.y, &pv, &row);
  const double x = conditional_[row].sample(u.x, &pu, nullptr);
  if (pdf) *pdf = pu * pv;
  return {x, v};
}

double Distribution2D::pdf(Vec2 p) const {
  if (p.x < 0 || p.x >= 1 || p.y < 0 || p.y >= 1) return 0.0;
  const auto row = std::min(static_cast<std::size_t>(p.y * static_cast<double>(conditional_.size())),
                            conditional_.size() - 1);
  return marginal_.pdf(p.y) * conditional_[row].pdf(p.x);
}

}  // namespace skin::render

namespace skin::render {

namespace {
std::uint32_t reverse_bits(std::uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
  v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
  return (v >> 16) | (v << 16);
}
// A bijection of 32-bit integers in which bit j of the result depends only on bits 0..j of the
// argument (an addition, and xors with products by even constants, carry information upward
// only): applied to bit-reversed fractions, a nested uniform (Owen) scramble. Constants: Burley
// 2020, sec. 3 (his variant of the Laine-Karras permutation).
std::uint32_t laine_karras(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}
// The Sobol sequence's second dimension is linear over GF(2) in the index bits: the xor of one
// table entry per index byte.
constexpr std::uint32_t sobol1_bits(std::uint32_t i) {
  // Direction numbers of the primitive polynomial x + 1: v_1 = 1/2, v_{k+1} = v_k xor v_k / 2
  // (m_k = 1, 3, 5, 15, 17, ...).
  std::uint32_t r = 0;
  for (std::uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1)
    if (i & 1u) r ^= v;
  return r;
}
struct Sobol1Table {
  std::uint32_t t[4][256] = {};
  constexpr Sobol1Table() {
    for (std::uint32_t k = 0; k < 4; ++k)
      for (std::uint32_t b = 0; b < 256; ++b) t[k][b] = sobol1_bits(b << (8 * k));
  }
};
constexpr Sobol1Table kSobol1;
constexpr double kFraction = 0x1p-32;
// Seeds of the coordinates of a dimension, apart from its index shuffle's.
constexpr std::uint32_t kSeedX = 0xa511e9b3u, kSeedY = 0x63d83595u;
}  // namespace

std::uint32_t sobol_dimension0(std::uint32_t i) { return reverse_bits(i); }  // van der Corput

std::uint32_t sobol_dimension1(std::uint32_t i) {
  return kSobol1.t[0][i & 0xffu] ^ kSobol1.t[1][(i >> 8) & 0xffu] ^ kSobol1.t[2][(i >> 16) & 0xffu] ^
         kSobol1.t[3][i >> 24];
}

std::uint32_t owen_scramble(std::uint32_t v, std::uint32_t seed) {
  return reverse_bits(laine_karras(reverse_bits(v), seed));
}

Sampler::Sampler(std::uint64_t seed, std::uint64_t stream, std::uint32_t index)
    : rng_(Pcg32::for_sample(seed, stream, index)), base_(mix64(seed ^ mix64(stream ^ 0x5bd1e995u))), key_(base_),
      reversed_index_(reverse_bits(index)), quasi_(true) {}

// Dimension with seed s: the sample's index shuffled, i = owen_scramble(index, s), is
// reverse_bits(laine_karras(reversed index, s)), so its first Sobol coordinate (the bit reversal
// of i) is laine_karras(reversed index, s) itself.
double Sampler::uniform() {
  if (!quasi_ || dim_ >= kQuasiDimensions) return rng_.uniform();
  const std::uint32_t s = next_seed();
  const std::uint32_t x = laine_karras(reversed_index_, s);
  return owen_scramble(x, s ^ kSeedX) * kFraction;
}

Vec2 Sampler::uniform2() {
  if (!quasi_ || dim_ >= kQuasiDimensions) {
    const double a = rng_.uniform();
    return {a, rng_.uniform()};
  }
  const std::uint32_t s = next_seed();
  const std::uint32_t x = laine_karras(reversed_index_, s);
  const std::uint32_t y = sobol_dimension1(reverse_bits(x));
  return {owen_scramble(x, s ^ kSeedX) * kFraction, owen_scramble(y, s ^ kSeedY) * kFraction};
}

}  // namespace skin::render
