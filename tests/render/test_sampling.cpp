// Sampling routines of the renderer: each sampler against its pdf with a chi-square test (fixed
// seeds), pdfs integrating to one, inversions round-tripping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sampler_checks.hpp"
#include "skin/render/microfacet.hpp"
#include "skin/render/profile_sampler.hpp"
#include "skin/render/sampling.hpp"
#include "test_support.hpp"

namespace skin::render {
namespace {
using namespace test;  // NOLINT(google-build-using-namespace)

TEST(ProfileSampler, EvalIntegratesToRdAndPdfToOne) {
  // eval() is rescaled so that 2 pi int R r dr = R_d exactly; pdf_radius integrates to 1.
  for (int c = 0; c < 3; ++c) {
    const TabulatedProfile p = skin_channel(c);
    SCOPED_TRACE(::testing::Message() << p);
    const auto& r = p.radii();
    double total = 0, prob = 0;
    for (std::size_t i = 0; i + 1 < r.size(); ++i) {
      total += simpson([&](double x) { return 2 * kPi * x * p.eval(x); }, r[i], r[i + 1], 20);
      prob += simpson([&](double x) { return p.pdf_radius(x); }, r[i], r[i + 1], 20);
    }
    EXPECT_NEAR(total, p.R_d(), 1e-6 * p.R_d());
    EXPECT_NEAR(prob, 1.0, 1e-9);
    // pdf_area = pdf_radius / (2 pi r), and its limit at r = 0 is finite and continuous.
    EXPECT_NEAR(p.pdf_area(0.5), p.pdf_radius(0.5) / (2 * kPi * 0.5), 1e-12);
    EXPECT_NEAR(p.pdf_area(0.0), p.pdf_area(1e-4), 1e-6 * p.pdf_area(1e-4));
  }
}

TEST(ProfileSampler, InvertRoundTrips) {
  const TabulatedProfile p = skin_channel(0);
  for (double u : {0.0, 0.01, 0.2, 0.5, 0.77, 0.99, 0.9999}) {
    const double r = p.sample_radius(u);
    EXPECT_NEAR(p.invert_radius(r), u, 1e-9) << "u=" << u << " r=" << r;
  }
}

TEST(ProfileSampler, ChiSquareAgainstTabulatedProfile) {
  // Bins equally spaced in log r; the expected probability of each is the integral of the
  // tabulated profile's f(r) = 2 pi r R(r) (its positive part), by Simpson over the bin,
  // independent of the sampler's own CDF.
  for (int c = 0; c < 3; ++c) {
    const TabulatedProfile p = skin_channel(c);
    SCOPED_TRACE(::testing::Message() << "channel " << c << " " << p);
    const auto& nodes = p.radii();
    std::vector<double> edges{0.0};
    for (int i = 0; i <= 60; ++i) edges.push_back(1e-3 * std::pow(p.r_max() / 1e-3, i / 60.0));
    edges.back() = p.r_max();
    // The density is piecewise linear between grid nodes: integrate node interval by node interval.
    auto integral = [&](double a, double b) {
      double s = 0;
      for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
        const double lo = std::max(a, nodes[i]), hi = std::min(b, nodes[i + 1]);
        if (hi > lo) s += simpson([&](double x) { return std::max(0.0, 2 * kPi * x * p.eval(x)); }, lo, hi, 4);
      }
      return s;
    };
    std::vector<double> prob(edges.size() - 1);
    double sum = 0;
    for (std::size_t i = 0; i < prob.size(); ++i) sum += prob[i] = integral(edges[i], edges[i + 1]);
    for (auto& x : prob) x /= sum;
    std::vector<double> counts(prob.size(), 0.0);
    Rng rng(42, static_cast<std::uint64_t>(c));
    constexpr int kN = 200000;
    for (int k = 0; k < kN; ++k) {
      const double r = p.sample_radius(rng.uniform());
      const auto it = std::upper_bound(edges.begin(), edges.end(), r);
      const auto bin = std::clamp<std::ptrdiff_t>(it - edges.begin() - 1, 0, static_cast<std::ptrdiff_t>(prob.size()) - 1);
      counts[static_cast<std::size_t>(bin)] += 1;
    }
    EXPECT_GT(chi_square_p(counts, prob, kN), 1e-3);
  }
}

TEST(Beckmann, NormalisedAndSamplesItsPdf) {
  for (double sigma : {0.35, 0.1, 0.8}) {
    const Beckmann b{sigma};
    SCOPED_TRACE(::testing::Message() << b);
    double p = 0, integral = 0;
    direction_chi_square([&](Vec2 u, Vec3* w) { *w = b.sample_h(u); return true; },
                         [&](const Vec3& h) { return b.pdf_h(h); }, 11, &p, &integral);
    EXPECT_GT(p, 1e-3);
    // int D(h) cos(theta_h) dh = 2 pi int D cos sin dtheta = 1, by Simpson in theta.
    const double norm = 2 * kPi * simpson([&](double t) {
      return b.D({std::sin(t), 0, std::cos(t)}) * std::cos(t) * std::sin(t); }, 0, kPi / 2, 4000);
    EXPECT_NEAR(norm, 1.0, 1e-6);
    for (Vec2 u : {Vec2{0.1, 0.2}, Vec2{0.7, 0.9}, Vec2{0.99, 0.5}}) {
      const Vec2 back = b.invert_h(b.sample_h(u));
      EXPECT_NEAR(back.x, u.x, 1e-9);
      EXPECT_NEAR(back.y, u.y, 1e-9);
    }
  }
}

TEST(ChiSquare, DetectsAWrongSampler) {
  // The test must be able to fail: a Beckmann sampler of RMS slope 0.37 checked against the pdf
  // of 0.35 (a 6 % error in roughness) is rejected.
  const Beckmann right{0.35}, wrong{0.37};
  double p = 0, integral = 0;
  direction_chi_square([&](Vec2 u, Vec3* w) { *w = wrong.sample_h(u); return true; },
                       [&](const Vec3& h) { return right.pdf_h(h); }, 11, &p, &integral);
  EXPECT_LT(p, 1e-3);
}

TEST(TorranceSparrow, SampledDirectionsFollowPdf) {
  const TorranceSparrow lobe(0.3, 0.35, 1.4);
  for (double theta_o : {0.1, 0.8, 1.3}) {
    SCOPED_TRACE(theta_o);
    const Vec3 wo{std::sin(theta_o), 0, std::cos(theta_o)};
    double p = 0, integral = 0;
    direction_chi_square([&](Vec2 u, Vec3* w) { double pdf; return lobe.sample(wo, u, w, &pdf); },
                         [&](const Vec3& wi) { return lobe.pdf(wo, wi); }, 12, &p, &integral);
    EXPECT_GT(p, 1e-3);
    EXPECT_LE(integral, 1.0 + 2e-3);  // mass below the horizon is lost, never created
  }
}

TEST(SpecularAlbedo, MatchesBruteForceHemisphereIntegral) {
  // rho_dr(theta) = int f_s cos dw (DJ06 eq 2) by a plain midpoint rule over (theta_i, phi_i),
  // independent of the lobe's importance sampling used to build the table.
  const SpecularAlbedo table(0.35, 1.4);
  const TorranceSparrow lobe(1.0, 0.35, 1.4);
  for (double theta_o : {0.0, 0.5, 1.0, 1.4}) {
    const Vec3 wo{std::sin(theta_o), 0, std::cos(theta_o)};
    double sum = 0;
    constexpr int kT = 400, kP = 400;
    for (int i = 0; i < kT; ++i)
      for (int j = 0; j < kP; ++j) {
        const double t = (i + 0.5) / kT * kPi / 2, ph = (j + 0.5) / kP * 2 * kPi;
        const Vec3 wi{std::sin(t) * std::cos(ph), std::sin(t) * std::sin(ph), std::cos(t)};
        sum += lobe.f(wo, wi) * wi.z * std::sin(t);
      }
    const double brute = sum * (kPi / 2 / kT) * (2 * kPi / kP);
    EXPECT_NEAR(table.rho_dr(std::cos(theta_o)), brute, 3e-3 + 0.01 * brute) << "theta_o " << theta_o;
  }
  // At normal incidence the lobe reflects about the Fresnel reflectance ((n - 1) / (n + 1))^2 =
  // 0.028 for n = 1.4, less what shadowing removes; the mean over a diffuse field is larger.
  EXPECT_GT(table.rho_dr(1.0), 0.015);
  EXPECT_LT(table.rho_dr(1.0), 0.03);
  EXPECT_GT(table.mean(), table.rho_dr(1.0));
  EXPECT_LT(table.mean(), 0.2);
}

TEST(Warps, ConeAndCosineHemisphereFollowTheirPdfs) {
  double p = 0, integral = 0;
  const double cmax = std::cos(0.4);
  direction_chi_square([&](Vec2 u, Vec3* w) { *w = sample_uniform_cone(u, cmax); return true; },
                       [&](const Vec3& w) { return w.z >= cmax ? pdf_uniform_cone(cmax) : 0.0; }, 13, &p, &integral);
  EXPECT_GT(p, 1e-3);
  direction_chi_square([&](Vec2 u, Vec3* w) { *w = sample_cosine_hemisphere(u); return true; },
                       [&](const Vec3& w) { return pdf_cosine_hemisphere(w.z); }, 14, &p, &integral);
  EXPECT_GT(p, 1e-3);
  EXPECT_NEAR(integral, 1.0, 1e-3);
}

TEST(Distribution1D, SampleInvertPdf) {
  const Distribution1D d({1, 0, 3, 2});
  for (double u : {0.05, 0.3, 0.6, 0.95}) {
    double pdf = 0;
    std::size_t bin = 0;
    const double x = d.sample(u, &pdf, &bin);
    EXPECT_NEAR(d.invert(x), u, 1e-12);
    EXPECT_NEAR(d.pdf(x), pdf, 1e-12);
    EXPECT_NE(bin, 1u);  // the empty bin is never sampled
  }
}

TEST(Rng, ReproducibleAndUniform) {
  Rng a = Rng::for_sample(1, 2, 3), b = Rng::for_sample(1, 2, 3), c = Rng::for_sample(1, 2, 4);
  EXPECT_EQ(a.next_u32(), b.next_u32());
  EXPECT_NE(b.next_u32(), c.next_u32());
  std::vector<double> counts(32, 0.0), prob(32, 1.0 / 32);
  Rng r(9, 1);
  for (int i = 0; i < 64000; ++i) counts[static_cast<std::size_t>(r.uniform() * 32)] += 1;
  EXPECT_GT(chi_square_p(counts, prob, 64000), 1e-3);
}

// The quasi-random sampler (Sampler, Burley 2020's padded Owen-scrambled Sobol sequence).

TEST(Sampler, SobolDimensionsAreTheKnownSequences) {
  // The first points of Sobol's first two dimensions in index order (x_i = xor of the direction
  // numbers v_k of the set bits of i; van der Corput, and m_k = 1, 3, 5: v = 1/2, 3/4, 5/8). In
  // Gray-code order (Antonov & Saleev) the same sets of 2^k points come in another order.
  const double x[8] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  const double y[8] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (std::uint32_t i = 0; i < 8; ++i) {
    EXPECT_EQ(sobol_dimension0(i) * 0x1p-32, x[i]) << i;
    EXPECT_EQ(sobol_dimension1(i) * 0x1p-32, y[i]) << i;
  }
}

TEST(Sampler, OwenScrambleIsABijectionThatKeepsElementaryIntervals) {
  // A nested uniform scramble permutes the 2^k intervals of length 2^-k among themselves for every
  // k: two fractions with the same first k bits keep a common first k bits, and 16-bit inputs
  // map one to one.
  std::vector<std::uint32_t> seen;
  for (std::uint32_t v = 0; v < 65536; ++v) seen.push_back(owen_scramble(v << 16, 0x1234567u) >> 16);
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(std::unique(seen.begin(), seen.end()) - seen.begin(), 65536);
  for (std::uint32_t k : {1u, 4u, 9u}) {
    const std::uint32_t a = 0x9abcdef0u, b = (a & ~((1u << (32 - k)) - 1)) | 0x155u;  // same first k bits
    EXPECT_EQ(owen_scramble(a, 77u) >> (32 - k), owen_scramble(b, 77u) >> (32 - k)) << k;
  }
}

// Points of one dimension (1D: y = 0) over the first n samples of a stream.
std::vector<Vec2> sampler_points(std::uint64_t stream, int n, int dim, bool two_d) {
  std::vector<Vec2> out;
  for (int i = 0; i < n; ++i) {
    Sampler s(7, stream, static_cast<std::uint32_t>(i));
    for (int d = 0; d < dim; ++d) two_d ? (void)s.uniform2() : (void)s.uniform();
    out.push_back(two_d ? s.uniform2() : Vec2{s.uniform(), 0});
  }
  return out;
}

TEST(Sampler, FirstPowerOfTwoSamplesAreStratifiedInEveryDimension) {
  // The first 2^k samples of a stream: one in each interval of length 2^-k in a 1D dimension, and
  // in a 2D dimension one in each elementary box of area 2^-k (2^a x 2^(k-a) boxes, every a): a
  // (0, k, 2)-net, for dimensions 0, 5 and 40 and two streams.
  for (std::uint64_t stream : {3u, 1000u})
    for (int dim : {0, 5, 40}) {
      SCOPED_TRACE(::testing::Message() << "stream " << stream << " dimension " << dim);
      for (int k : {4, 6}) {
        const int n = 1 << k;
        std::vector<int> bins(static_cast<std::size_t>(n), 0);
        for (const Vec2& p : sampler_points(stream, n, dim, false)) ++bins[static_cast<std::size_t>(p.x * n)];
        EXPECT_EQ(*std::min_element(bins.begin(), bins.end()), 1) << "1D, 2^" << k;
        const std::vector<Vec2> pts = sampler_points(stream, n, dim, true);
        for (int a = 0; a <= k; ++a) {
          const int nx = 1 << a, ny = 1 << (k - a);
          std::vector<int> box(static_cast<std::size_t>(n), 0);
          for (const Vec2& p : pts) ++box[static_cast<std::size_t>(static_cast<int>(p.y * ny) * nx + static_cast<int>(p.x * nx))];
          EXPECT_EQ(*std::min_element(box.begin(), box.end()), 1) << "2D, 2^" << k << ", " << nx << " x " << ny;
        }
      }
    }
}

TEST(Sampler, UniformAcrossStreamsAndDimensionsIndependent) {
  // Any one number over many streams is uniform, and two dimensions of one sample are independent:
  // chi-square of (dimension 2 x, dimension 3 x) on 16 x 16 bins over 64 samples of 400 streams,
  // and of one 1D dimension on 64 bins. A sampler that reused one dimension's scramble for the
  // next (the points on a diagonal) fails the joint test.
  std::vector<double> joint(256, 0.0), joint_prob(256, 1.0 / 256), one(64, 0.0), one_prob(64, 1.0 / 64),
      same(256, 0.0);
  constexpr int kStreams = 400, kSamples = 64;
  for (int st = 0; st < kStreams; ++st)
    for (int i = 0; i < kSamples; ++i) {
      Sampler s(11, static_cast<std::uint64_t>(st), static_cast<std::uint32_t>(i));
      (void)s.uniform2();
      (void)s.uniform();
      const double a = s.uniform2().x, b = s.uniform2().x;
      joint[static_cast<std::size_t>(static_cast<int>(a * 16) * 16 + static_cast<int>(b * 16))] += 1;
      one[static_cast<std::size_t>(b * 64)] += 1;
      Sampler t(11, static_cast<std::uint64_t>(st), static_cast<std::uint32_t>(i)), u = t;
      const double c = t.uniform2().x;
      const double d = u.uniform2().x;  // the same dimension again
      same[static_cast<std::size_t>(static_cast<int>(c * 16) * 16 + static_cast<int>(d * 16))] += 1;
    }
  EXPECT_GT(chi_square_p(joint, joint_prob, kStreams * kSamples), 1e-3);
  EXPECT_GT(chi_square_p(one, one_prob, kStreams * kSamples), 1e-3);
  EXPECT_LT(chi_square_p(same, joint_prob, kStreams * kSamples), 1e-3);
}

TEST(Sampler, BlocksRestartTheirDimensionsAndTheRandomModeIsPcg) {
  // start_block(b) gives the same numbers whatever was drawn before it.
  Sampler a(5, 9, 3), b(5, 9, 3);
  (void)a.uniform();
  for (int i = 0; i < 7; ++i) (void)b.uniform2();
  a.start_block(12);
  b.start_block(12);
  EXPECT_EQ(a.uniform(), b.uniform());
  EXPECT_EQ(a.uniform2().y, b.uniform2().y);
  // Past kQuasiDimensions the numbers are PCG32's, as in the random mode.
  Sampler r(Rng(4, 2));
  Rng g(4, 2);
  EXPECT_EQ(r.uniform(), g.uniform());
  const Vec2 v = r.uniform2();
  EXPECT_EQ(v.x, g.uniform());
  EXPECT_EQ(v.y, g.uniform());
}

}  // namespace
}  // namespace skin::render
