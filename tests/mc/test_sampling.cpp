// Sampling routines of the Monte Carlo solver as matched sets: sample / pdf / invert agree,
// chi-square goodness of fit with fixed seeds, and the Fresnel helper against the core one.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "skin/mc/sampling.hpp"
#include "test_support.hpp"

namespace {

using namespace skin::mc;

using skin::test::chi_square_equiprobable;

// Upper 0.1 % point of chi-square with 49 degrees of freedom (standard tables): a correct sampler
// fails once in a thousand seeds; the seeds are fixed, so the test is deterministic.
constexpr double kChi2_49_p001 = 85.35;

TEST(HenyeyGreenstein, PdfIntegratesToOneAndHasMeanCosineG) {
  for (double g : {-0.5, 0.0, 0.3, 0.75, 0.9}) {
    // Midpoint rule with many panels (the pdf is smooth for |g| < 1).
    const int n = 200000;
    double total = 0, mean = 0;
    for (int i = 0; i < n; ++i) {
      const double mu = -1.0 + (i + 0.5) * 2.0 / n;
      const double p = hg_pdf_cos(g, mu) * 2.0 / n;
      total += p;
      mean += mu * p;
    }
    EXPECT_NEAR(total, 1.0, 1e-6) << "g=" << g;
    EXPECT_NEAR(mean, g, 1e-5) << "g=" << g;
  }
}

TEST(HenyeyGreenstein, InvertIsTheInverseOfSampleAndTheIntegralOfPdf) {
  for (double g : {-0.5, 0.0, 0.3, 0.9}) {
    for (double u : {0.0, 0.01, 0.2, 0.5, 0.77, 0.999}) {
      const double mu = hg_sample_cos(g, u);
      EXPECT_NEAR(hg_invert_cos(g, mu), u, 1e-9) << "g=" << g << " u=" << u;
    }
    // CDF derivative equals the pdf.
    for (double mu : {-0.9, -0.2, 0.4, 0.95}) {
      const double h = 1e-6;
      const double d = (hg_invert_cos(g, mu + h) - hg_invert_cos(g, mu - h)) / (2 * h);
      EXPECT_NEAR(d, hg_pdf_cos(g, mu), 1e-5 * (1 + hg_pdf_cos(g, mu))) << "g=" << g;
    }
  }
}

TEST(HenyeyGreenstein, ChiSquareOfSamples) {
  for (double g : {-0.3, 0.0, 0.75, 0.9}) {
    Rng rng(42, static_cast<std::uint64_t>(100 * (g + 1)));
    const double chi2 = chi_square_equiprobable(
        200000, 50, [&] { return hg_invert_cos(g, hg_sample_cos(g, rng.uniform())); });
    // Transforming by the exact CDF makes the samples uniform iff the sampler is right; the
    // round trip alone could hide a wrong CDF, so also bin directly against the pdf's CDF below.
    EXPECT_LT(chi2, kChi2_49_p001) << "g=" << g;
  }
  // Direct check against the pdf: expected counts from integrating hg_pdf_cos over 40 bins of mu.
  const double g = 0.9;
  Rng rng(7, 0);
  const int bins = 40, n = 200000;
  std::vector<double> count(bins, 0.0);
  for (int i = 0; i < n; ++i) {
    const double mu = hg_sample_cos(g, rng.uniform());
    count[std::min(bins - 1, static_cast<int>((mu + 1.0) / 2.0 * bins))] += 1;
  }
  double chi2 = 0;
  for (int b = 0; b < bins; ++b) {
    double p = 0;  // midpoint rule inside the bin
    const int m = 2000;
    for (int k = 0; k < m; ++k) {
      const double mu = -1.0 + (b + (k + 0.5) / m) * 2.0 / bins;
      p += hg_pdf_cos(g, mu) * 2.0 / bins / m;
    }
    const double e = p * n;
    chi2 += (count[b] - e) * (count[b] - e) / e;
  }
  EXPECT_LT(chi2, 73.4);  // upper 0.1 % point for 39 degrees of freedom
}

TEST(OpticalDepth, MatchedSetAndChiSquare) {
  for (double tau : {0.0, 0.3, 2.0, 7.5}) {
    EXPECT_NEAR(sample_optical_depth(invert_optical_depth(tau)), tau, 1e-12);
    EXPECT_NEAR(pdf_optical_depth(tau), std::exp(-tau), 1e-15);
  }
  Rng rng(3, 9);
  const double chi2 = chi_square_equiprobable(200000, 50, [&] {
    const double tau = sample_optical_depth(rng.uniform_open0());
    return 1.0 - invert_optical_depth(tau);  // the CDF of tau, uniform if tau ~ exp(-tau)
  });
  EXPECT_LT(chi2, kChi2_49_p001);
}

TEST(HenyeyGreenstein, PreparedSamplerIsTheSameFormula) {
  for (double g : {-0.5, 0.0, 1e-7, 0.3, 0.9, 0.99}) {
    const HenyeyGreenstein hg(g);
    for (double u : {0.0, 1e-9, 0.01, 0.2, 0.5, 0.77, 0.999, 1.0 - 0x1p-53})
      EXPECT_NEAR(hg.sample_cos(u), hg_sample_cos(g, u), 1e-12) << "g=" << g << " u=" << u;
  }
  // And its samples follow the pdf: through the exact CDF they are uniform.
  const HenyeyGreenstein hg(0.9);
  Rng rng(5, 1);
  EXPECT_LT(chi_square_equiprobable(200000, 50,
                                    [&] { return hg_invert_cos(0.9, hg.sample_cos(rng.uniform())); }),
            kChi2_49_p001);
}

// The ziggurat draws of the photon loop follow exp(-tau): the CDF transform is uniform (body),
// and the tail beyond tau = 7.7 (the ziggurat's base strip, drawn by its own branch) holds
// exp(-7.7) of the samples: 2^21 draws expect 951 +- 31 there.
TEST(OpticalDepth, ZigguratIsExponentialIncludingTheTail) {
  Rng rng(11, 2);
  const std::size_t n = 1 << 21;
  std::size_t tail = 0, deep = 0;
  const double chi2 = chi_square_equiprobable(n, 50, [&] {
    const double tau = sample_optical_depth(rng);
    tail += tau > 7.7;
    deep += tau > 10.0;
    return 1.0 - invert_optical_depth(tau);
  });
  EXPECT_LT(chi2, kChi2_49_p001);
  const double expected = static_cast<double>(n) * std::exp(-7.7);
  EXPECT_NEAR(static_cast<double>(tail), expected, 4 * std::sqrt(expected));
  const double expected_deep = static_cast<double>(n) * std::exp(-10.0);  // 95: beyond the base
  EXPECT_NEAR(static_cast<double>(deep), expected_deep, 4 * std::sqrt(expected_deep));
  // Mean 1 and variance 1: standard errors 1/sqrt(n) and sqrt(8/n).
  Rng r2(12, 0);
  double m1 = 0, m2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = sample_optical_depth(r2);
    m1 += t;
    m2 += t * t;
  }
  m1 /= static_cast<double>(n);
  m2 /= static_cast<double>(n);
  EXPECT_NEAR(m1, 1.0, 4 / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(m2 - m1 * m1, 1.0, 4 * std::sqrt(8 / static_cast<double>(n)));
}

TEST(Azimuth, MatchesTrigonometryAndIsUniform) {
  Rng rng(13, 0);
  double worst = 0;
  for (int i = 0; i < 100000; ++i) {
    const std::uint64_t bits = rng.next_u64();
    const Azimuth a = azimuth(bits);
    // phi on the generator's 2^-61 grid, as the table method reads it
    const double phi = 2.0 * M_PI * static_cast<double>(bits >> 3) * 0x1p-61;
    worst = std::max({worst, std::abs(a.cos_phi - std::cos(phi)), std::abs(a.sin_phi - std::sin(phi))});
  }
  // The reference phi is itself rounded (half an ulp of 2 pi is 4.4e-16), and the table method
  // rounds a few times: 2e-15 bounds both.
  EXPECT_LT(worst, 2e-15);
  // Sector edges and the last value before 2 pi.
  EXPECT_NEAR(azimuth(0).cos_phi, 1.0, 1e-16);
  EXPECT_NEAR(azimuth(0).sin_phi, 0.0, 1e-16);
  EXPECT_NEAR(azimuth(~0ULL).sin_phi, 0.0, 1e-15);
  EXPECT_NEAR(azimuth(1ULL << 62).cos_phi, 0.0, 1e-16);  // phi = pi / 2
  EXPECT_NEAR(azimuth(1ULL << 62).sin_phi, 1.0, 1e-16);
  Rng r2(14, 0);
  EXPECT_LT(chi_square_equiprobable(200000, 50, [&] {
              const Azimuth a = azimuth(r2.next_u64());
              const double phi = std::atan2(a.sin_phi, a.cos_phi);
              return (phi < 0 ? phi + 2 * M_PI : phi) / (2 * M_PI);
            }),
            kChi2_49_p001);
}

// The scattered direction is a unit vector at angle theta from the old one, and its azimuth
// about the old one is uniform (measured in an independent frame), for old directions anywhere,
// the poles included.
TEST(ScatterDirection, UnitAngleThetaAndUniformAzimuth) {
  Rng rng(15, 0);
  for (const auto& u0 : std::vector<std::array<double, 3>>{
           {0, 0, 1}, {0, 0, -1}, {0.6, 0, 0.8}, {0.48, -0.6, -0.64}, {1, 0, 0}, {0, 1e-9, -1}}) {
    const double norm = std::sqrt(u0[0] * u0[0] + u0[1] * u0[1] + u0[2] * u0[2]);
    const double vx = u0[0] / norm, vy = u0[1] / norm, vz = u0[2] / norm;
    // An independent frame (p, q) perpendicular to v: p from the cross product with the axis least
    // aligned with v.
    double px = 0, py = 0, pz = 0;
    if (std::abs(vx) < 0.5) {  // p = x_hat x v, normalised
      px = 0; py = -vz; pz = vy;
    } else {  // p = z_hat x v
      px = -vy; py = vx; pz = 0;
    }
    const double pn = std::sqrt(px * px + py * py + pz * pz);
    px /= pn; py /= pn; pz /= pn;
    const double qx = vy * pz - vz * py, qy = vz * px - vx * pz, qz = vx * py - vy * px;
    const double cos_t = 0.3, sin_t = std::sqrt(1 - cos_t * cos_t);
    const double chi2 = chi_square_equiprobable(50000, 50, [&] {
      const Azimuth a = azimuth(rng.next_u64());
      double ux = vx, uy = vy, uz = vz;
      scatter_direction(ux, uy, uz, cos_t, sin_t * a.cos_phi, sin_t * a.sin_phi);
      EXPECT_NEAR(ux * ux + uy * uy + uz * uz, 1.0, 1e-14);
      EXPECT_NEAR(ux * vx + uy * vy + uz * vz, cos_t, 1e-14);
      const double phi = std::atan2(ux * qx + uy * qy + uz * qz, ux * px + uy * py + uz * pz);
      return (phi < 0 ? phi + 2 * M_PI : phi) / (2 * M_PI);
    });
    EXPECT_LT(chi2, kChi2_49_p001) << vx << ' ' << vy << ' ' << vz;
  }
}

TEST(Rng, UniformRangesAndStreamsDiffer) {
  Rng a(1, 0), b(1, 1), c(1, 0);
  double sum = 0;
  for (int i = 0; i < 100000; ++i) {
    const double u = a.uniform();
    const double v = b.uniform_open0();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ASSERT_GT(v, 0.0);
    ASSERT_LE(v, 1.0);
    sum += u;
  }
  // Mean of 1e5 uniforms: standard deviation 1/sqrt(12e5) = 9e-4; 5 sigma.
  EXPECT_NEAR(sum / 100000, 0.5, 4.6e-3);
  Rng a2(1, 0);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(a2.next_u64(), c.next_u64());  // reproducible
  Rng d(2, 0);
  EXPECT_NE(Rng(1, 0).next_u64(), d.next_u64());
  EXPECT_NE(Rng(1, 0).next_u64(), Rng(1, 1).next_u64());
}

}  // namespace
