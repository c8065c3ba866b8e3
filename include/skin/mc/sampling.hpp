#pragma once
// Random numbers and the sampling routines of the Monte Carlo solver, as matched sets
// (sample / pdf / invert), so that tests can check each against the others.
#include <cmath>
#include <cstdint>
#include <iosfwd>

namespace skin::mc {

// SplitMix64 (Steele, Lea & Flood 2014): a bijective 64-bit mixer. Used to derive independent
// generator states from (seed, stream) so that results do not depend on the thread schedule.
constexpr std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// xoshiro256+ (Blackman & Vigna 2018): fast, 2^256 - 1 period; its top 53 bits (the only ones
// used, for doubles) pass BigCrush. One generator per stream (batch of photons).
class Rng {
 public:
  // Stream `stream` of seed `seed`: the state is four SplitMix64 outputs of a mix of both.
  Rng(std::uint64_t seed, std::uint64_t stream) {
    std::uint64_t sm = seed ^ (0xD1B54A32D192ED03ULL * (stream + 1));
    splitmix64(sm);  // decorrelate neighbouring (seed, stream) pairs
    for (auto& w : s_) w = splitmix64(sm);
  }
  std::uint64_t next_u64() {
    const std::uint64_t result = s_[0] + s_[3];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = (s_[3] << 45) | (s_[3] >> 19);
    return result;
  }
  // Uniform in [0, 1), multiples of 2^-53.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  // Uniform in (0, 1]: safe for -log(u).
  double uniform_open0() { return static_cast<double>((next_u64() >> 11) + 1) * 0x1.0p-53; }

 private:
  std::uint64_t s_[4];
};

// Henyey-Greenstein phase function in the cosine of the scattering angle, normalised over
// cos_theta in [-1, 1]:  p(mu) = (1 - g^2) / (2 (1 + g^2 - 2 g mu)^{3/2})  (Henyey & Greenstein
// 1941; the 1/(4 pi) solid-angle form times 2 pi). Mean cosine g.
double hg_pdf_cos(double g, double mu);
// Inverse-CDF sample for u in [0, 1): mu = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g),
// and mu = 2u - 1 for |g| < 1e-6 (the limit). Result clamped to [-1, 1] against rounding.
inline double hg_sample_cos(double g, double u) {
  if (std::abs(g) < 1e-6) return 2.0 * u - 1.0;
  const double t = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  const double mu = (1.0 + g * g - t * t) / (2.0 * g);
  return mu < -1.0 ? -1.0 : (mu > 1.0 ? 1.0 : mu);
}
// The CDF, u = P(cos_theta <= mu): inverts hg_sample_cos.
double hg_invert_cos(double g, double mu);

// Exponential free path in optical depth: tau = -ln(u), u in (0, 1]; pdf exp(-tau);
// invert: u = exp(-tau).
inline double sample_optical_depth(double u) { return -std::log(u); }
inline double pdf_optical_depth(double tau) { return tau < 0 ? 0.0 : std::exp(-tau); }
inline double invert_optical_depth(double tau) { return std::exp(-tau); }

// Fresnel reflectance for unpolarised light from index n1 into n2 at incidence cosine cos_i > 0,
// and the cosine of the refracted ray (0 at and beyond total internal reflection, where R = 1).
struct FresnelResult {
  double R;
  double cos_t;
};
inline FresnelResult fresnel(double cos_i, double n1, double n2) {
  const double eta = n1 / n2;
  const double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return {1.0, 0.0};
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  return {0.5 * (rs * rs + rp * rp), cos_t};
}

}  // namespace skin::mc
