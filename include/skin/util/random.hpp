#pragma once
// Random number generators of the project, in one place. Two generators remain, on purpose: each
// one's stream is part of a result the project keeps reproducible bit for bit. The Monte Carlo
// reference draws from Xoshiro256Plus (its seeded runs are in tests/golden/golden.json) and the
// renderer from Pcg32 (a seed gives the same image at any thread count; its camera samples are
// quasi-random, skin/render/sampling.hpp's Sampler, which falls back to Pcg32); changing either
// generator would change those numbers. Both are counter-free, seeded per (seed, stream), so
// results never depend on the thread schedule. Tested in tests/util/test_numerics.cpp.
#include <cstdint>

namespace skin::util {

// SplitMix64 (Steele, Lea & Flood 2014): advances `state` by the golden-ratio increment and
// returns a bijective 64-bit mix of it. Derives generator states from seeds.
constexpr std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
// The same mix of a value (one SplitMix64 step from state x), as a pure function.
constexpr std::uint64_t mix64(std::uint64_t x) { return splitmix64(x); }

// xoshiro256+ (Blackman & Vigna 2018): fast, 2^256 - 1 period; its top 53 bits (the only ones
// used, for doubles) pass BigCrush. The Monte Carlo solver runs one per batch of photons.
class Xoshiro256Plus {
 public:
  // Stream `stream` of seed `seed`: the state is four SplitMix64 outputs of a mix of both.
  Xoshiro256Plus(std::uint64_t seed, std::uint64_t stream) {
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

// PCG32 (O'Neill 2014, "PCG: a family of simple fast space-efficient statistically good
// algorithms for random number generation", the XSH-RR output function): 64-bit LCG state, one
// of 2^63 streams. The renderer seeds one per pixel sample (for_sample), so an image does not
// depend on how pixels are spread over threads.
class Pcg32 {
 public:
  Pcg32(std::uint64_t seed, std::uint64_t stream) : inc_((stream << 1u) | 1u) {
    next_u32();
    state_ += seed;
    next_u32();
  }
  // The generator of one (pixel, sample) of a seeded image.
  static Pcg32 for_sample(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    return Pcg32(mix64(seed ^ mix64(pixel)), mix64(sample + 0x632be59bd9b4e019ULL * (pixel + 1)));
  }
  std::uint32_t next_u32() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
  }
  // Uniform in [0, 1), multiples of 2^-32.
  double uniform() { return static_cast<double>(next_u32()) * 0x1p-32; }

 private:
  std::uint64_t state_ = 0, inc_ = 1;
};

}  // namespace skin::util
