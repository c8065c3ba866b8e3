// The Monte Carlo solver against published benchmarks, exact answers, its own statistics, and
// the diffusion model where diffusion is accurate. Photon counts are small (the whole binary runs
// in seconds); tolerances are multiples of the reported standard errors.
#include <gtest/gtest.h>

#include <boost/math/special_functions/expint.hpp>

#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>
#include <vector>

#include "skin/mc/mc.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"
#include "test_support.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/stack.hpp"

namespace {

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::kInfinity;
namespace mc = skin::mc;

LayerStack one_layer(double sigma_a, double sigma_s_prime, double d, double eta, double g,
                     double eta_above = 1.0, double eta_below = 1.0) {
  LayerStack s;
  s.layers = {Layer{sigma_a, sigma_s_prime, d, eta, g}};
  s.eta_above = eta_above;
  s.eta_below = eta_below;
  return s;
}

mc::Options opts(std::uint64_t photons, std::uint64_t seed = 1, int threads = 0) {
  mc::Options o;
  o.photons = photons;
  o.seed = seed;
  o.threads = threads;
  return o;
}

// --- Published benchmarks ----------------------------------------------------------------

TEST(MonteCarloBenchmark, MatchedSlabVanDeHulst) {
  // Wang, Jacques & Zheng 1995 (MCML paper), Table 1: slab with n = 1 (matched), mu_a = 10/cm,
  // mu_s = 90/cm, g = 0.75, d = 0.02 cm; van de Hulst's (1980) tabulated values R_d = 0.09739
  // and total transmittance T = 0.66096 (unscattered part included, as in our T_d).
  // In mm: sigma_a = 1, sigma_s = 9 (sigma_s' = 2.25), d = 0.2.
  const auto r = mc::simulate(one_layer(1.0, 9.0 * 0.25, 0.2, 1.0, 0.75), opts(400000));
  // 4 standard errors (a correct solver fails 6e-5 of the time) plus the rounding of the table.
  EXPECT_NEAR(r.R_d, 0.09739, 4 * r.R_d_se + 5e-6) << r;
  EXPECT_NEAR(r.T_d, 0.66096, 4 * r.T_d_se + 5e-6) << r;
  EXPECT_LT(r.R_d_se, 6e-4) << r;
  EXPECT_EQ(r.R_specular, 0.0);
}

TEST(MonteCarloBenchmark, SemiInfiniteIsotropicMatchedChandrasekhar) {
  // Semi-infinite medium, matched boundary, isotropic scattering, albedo 0.9 (mu_a = 10/cm,
  // mu_s = 90/cm, g = 0). Exact: the plane albedo at normal incidence, 1 - H(1) sqrt(1 - omega)
  // (Chandrasekhar 1960, Radiative Transfer, ch. V), with H computed from its integral equation
  // (tests/common/test_support.hpp; 0.41495).
  const double exact = 1.0 - skin::test::chandrasekhar_H(0.9, 1.0) * std::sqrt(0.1);
  EXPECT_NEAR(exact, 0.41495, 1e-5);  // regression guard of the H computation itself
  const auto r = mc::simulate(one_layer(1.0, 9.0, kInfinity, 1.0, 0.0), opts(200000));
  EXPECT_NEAR(r.R_d, exact, 4 * r.R_d_se) << r << " exact " << exact;
}

TEST(MonteCarloBenchmark, SemiInfiniteIsotropicMismatchedGiovanelli) {
  // The MCML paper's semi-infinite benchmark (Wang, Jacques & Zheng 1995, after Giovanelli 1955):
  // mu_a = 10/cm, mu_s = 90/cm, g = 0, n = 1.5 under air; total reflectance (specular 0.04
  // included, per incident power) 0.2600. Tolerance: 4 standard errors plus the table's rounding.
  const auto r = mc::simulate(one_layer(1.0, 9.0, kInfinity, 1.5, 0.0), opts(200000));
  EXPECT_NEAR(r.R_specular, 0.04, 1e-15);
  const double se_incident = r.R_d_se * (1 - r.R_specular);
  EXPECT_NEAR(r.R_specular + r.R_d_incident, 0.2600, 4 * se_incident + 5e-5) << r;
}

// --- Exact answers -------------------------------------------------------------------------

TEST(MonteCarloExact, NonAbsorbingSemiInfiniteReflectsEverything) {
  // Without absorption every packet leaves through the top eventually (a recurrent walk in depth)
  // with its full weight: R_d = 1, matched or not. The number of scatterings before the return
  // has infinite mean (P(N > n) ~ n^-1/2): the few packets still travelling after the longest
  // path allowed end there, their weight counted as lost, so that R_d + lost = 1 and every run
  // ends. Seed 1 with 2000 photons took minutes before that bound (issue 29); now ~1 s of CPU.
  for (double eta : {1.0, 1.4}) {
    const auto r = mc::simulate(one_layer(0.0, 1.0, kInfinity, eta, 0.0), opts(2000, 1));
    EXPECT_NEAR(r.R_d + r.lost, 1.0, 1e-12) << r;
    EXPECT_LT(r.lost, 0.01) << r;
    EXPECT_EQ(r.T_d, 0.0);
  }
  // With absorption no packet comes near the bound.
  EXPECT_EQ(mc::simulate(one_layer(0.01, 1.0, kInfinity, 1.4, 0.9), opts(2000, 1)).lost, 0.0);
}

// Issue 29: `skin mc --layer sigma_a=0,sigma_s_prime=1 --photons 200` (g 0.9, eta 1.4) ran for
// minutes without an estimate. The pilot ends (a few hundredths of a second of CPU plus at most
// one longest path) and measures a rate; the run of 200 photons ends too.
TEST(MonteCarloEstimate, PilotAndRunEndInANonAbsorbingHalfSpace) {
  const LayerStack s = one_layer(0.0, 1.0, kInfinity, 1.4, 0.9);
  const auto t0 = std::chrono::steady_clock::now();
  const double rate = mc::photons_per_second(s, opts(200));
  EXPECT_GT(rate, 0.0);
  EXPECT_TRUE(std::isfinite(rate));
  const auto r = mc::simulate(s, opts(200));
  EXPECT_NEAR(r.R_d + r.lost, 1.0, 1e-12) << r;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0);
}

TEST(MonteCarloEstimate, RefusesARunOfAWeekWithTheCommandLinesLine) {
  mc::Options o = opts(10'000'000'000'000ULL, 1, 2);
  try {
    (void)mc::estimate(one_layer(0.1, 1.0, kInfinity, 1.4, 0.9), o);
    FAIL() << "not refused";
  } catch (const skin::util::InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("a Monte Carlo run of 10000000000000 photons would take about ", 0), 0u) << m;
    EXPECT_NE(m.find(" on 2 threads (estimate from the measured speed): refused, make it smaller"),
              std::string::npos) << m;
  }
  o.photons = 1000;
  const skin::util::WorkEstimate e = mc::estimate(one_layer(0.1, 1.0, kInfinity, 1.4, 0.9), o);
  EXPECT_FALSE(e.long_run()) << e.text;
  EXPECT_EQ(e.threads, 2);
}

// Cancellation is polled within photons, not only between batches: in a non-absorbing
// half-space one batch of 1000 photons can take many seconds.
TEST(MonteCarloCancel, StopsWithinASecondWhateverTheMedium) {
  const LayerStack s = one_layer(0.0, 1.0, kInfinity, 1.4, 0.9);
  skin::util::cancel::reset();
  std::chrono::steady_clock::time_point requested;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    requested = std::chrono::steady_clock::now();
    skin::util::cancel::request();
  });
  EXPECT_THROW((void)mc::simulate(s, opts(100'000'000, 1, 1)), skin::util::Cancelled);
  const double after = std::chrono::duration<double>(std::chrono::steady_clock::now() - requested).count();
  canceller.join();
  skin::util::cancel::reset();
  EXPECT_LT(after, 1.0);
  EXPECT_THROW((void)[&] {
    skin::util::cancel::request();
    struct Reset { ~Reset() { skin::util::cancel::reset(); } } reset;
    return mc::photons_per_second(s, opts(100'000'000));
  }(), skin::util::Cancelled);
}

TEST(MonteCarloExact, NonAbsorbingSlabConservesEnergy) {
  for (double eta : {1.0, 1.4}) {
    auto s = one_layer(0.0, 2.0, 1.0, eta, 0.8, 1.0, 1.33);
    const auto r = mc::simulate(s, opts(20000));
    EXPECT_NEAR(r.R_d + r.T_d, 1.0, 1e-12) << r;
  }
}

TEST(MonteCarloExact, NonScatteringSlabBetweenFresnelInterfaces) {
  // A purely absorbing slab (scattering negligible) with n = 1.5 in air: the beam bounces between
  // the faces. With a = exp(-sigma_a d) and F = ((n - 1)/(n + 1))^2 at normal incidence, per power
  // that entered: T = (1 - F) a / (1 - F^2 a^2), R = F (1 - F) a^2 / (1 - F^2 a^2).
  const double sigma_a = 1.0, d = 0.5, n = 1.5;
  const auto r = mc::simulate(one_layer(sigma_a, 1e-12, d, n, 0.0), opts(100000));
  const double a = std::exp(-sigma_a * d), F = std::pow((n - 1) / (n + 1), 2);
  EXPECT_NEAR(r.T_d, (1 - F) * a / (1 - F * F * a * a), 4 * r.T_d_se) << r;
  EXPECT_NEAR(r.R_d, F * (1 - F) * a * a / (1 - F * F * a * a), 4 * r.R_d_se + 1e-9) << r;
  EXPECT_NEAR(r.R_specular, F, 1e-15);
  EXPECT_NEAR(r.R_d_incident, r.R_d * (1 - F), 1e-15);
  EXPECT_NEAR(r.T_d_incident, r.T_d * (1 - F), 1e-15);
  // All reflected light comes straight back up the beam: the first annulus holds it all.
  EXPECT_NEAR(r.R[0] * M_PI * std::pow(r.r_mm[0] * 2, 2), r.R_d, 1e-9 + 1e-9 * r.R_d);
}

TEST(MonteCarloExact, SplittingALayerChangesNothing) {
  // Two identical layers with matched indices are one layer: the interface consumes no random
  // numbers and carries the optical depth over, so the same seed gives (up to the rounding of the
  // positions) the same paths.
  LayerStack one = one_layer(0.1, 1.0, 2.0, 1.4, 0.9);
  LayerStack two = one;
  two.layers = {Layer{0.1, 1.0, 0.7, 1.4, 0.9}, Layer{0.1, 1.0, 1.3, 1.4, 0.9}};
  const auto a = mc::simulate(one, opts(20000));
  const auto b = mc::simulate(two, opts(20000));
  EXPECT_NEAR(a.R_d, b.R_d, 0.2 * a.R_d_se) << a << '\n' << b;
  EXPECT_NEAR(a.T_d, b.T_d, 0.2 * a.T_d_se) << a << '\n' << b;
}

TEST(MonteCarloProfile, IntegratesToTheTotal) {
  // 2 pi int R(r) r dr over the annuli = the reflectance that left within r_max.
  auto o = opts(20000);
  o.r_max = 30;  // ~30 transport mean free paths: nearly everything
  o.bins = 300;
  const auto r = mc::simulate(one_layer(0.1, 1.0, kInfinity, 1.4, 0.9), o);
  double total = 0;
  const double dr = o.r_max / static_cast<double>(o.bins);
  for (std::size_t i = 0; i < r.R.size(); ++i) total += r.R[i] * M_PI * dr * dr * (2.0 * static_cast<double>(i) + 1);
  EXPECT_LE(total, r.R_d * (1 + 1e-12));
  EXPECT_NEAR(total, r.R_d, 1e-3 * r.R_d) << r;
  EXPECT_NEAR(r.r_mm[0], dr / 2, 1e-15);
  EXPECT_NEAR(r.r_mm.back(), o.r_max - dr / 2, 1e-12);
  // R(r) decreases away from the entry point (checked where the estimate is precise).
  EXPECT_GT(r.R[0], r.R[20]);
  EXPECT_GT(r.R[20], r.R[100]);
}

// --- Statistics and determinism -------------------------------------------------------------

TEST(MonteCarloStatistics, DifferentSeedsAgreeWithinTheirStandardErrors) {
  // Ten independent runs: chi-square of their deviations from the weighted mean, 9 degrees of
  // freedom; 27.88 is the upper 0.1 % point. Also for one profile bin and for T_d.
  const auto stack = one_layer(0.05, 1.0, 3.0, 1.4, 0.9);
  auto o = opts(10000);
  o.r_max = 5;
  o.bins = 10;
  std::vector<mc::Result> runs;
  for (std::uint64_t seed = 11; seed <= 20; ++seed) {
    o.seed = seed;
    runs.push_back(mc::simulate(stack, o));
  }
  auto chi2 = [&](auto value, auto se) {
    double sw = 0, swx = 0;
    for (const auto& r : runs) {
      const double wi = 1 / (se(r) * se(r));
      sw += wi;
      swx += wi * value(r);
    }
    const double mean = swx / sw;
    double c = 0;
    for (const auto& r : runs) c += std::pow((value(r) - mean) / se(r), 2);
    return c;
  };
  const double c_R = chi2([](const mc::Result& r) { return r.R_d; }, [](const mc::Result& r) { return r.R_d_se; });
  const double c_T = chi2([](const mc::Result& r) { return r.T_d; }, [](const mc::Result& r) { return r.T_d_se; });
  const double c_bin = chi2([](const mc::Result& r) { return r.R[3]; }, [](const mc::Result& r) { return r.R_se[3]; });
  EXPECT_LT(c_R, 27.88);
  EXPECT_LT(c_T, 27.88);
  EXPECT_LT(c_bin, 27.88);
  // And the errors are not grossly overstated: chi-square above the lower 0.1 % point (1.15).
  EXPECT_GT(c_R, 1.15);
  EXPECT_GT(c_bin, 1.15);
}

TEST(MonteCarloStatistics, SameSeedSameResultWhateverTheThreadCount) {
  const auto stack = skin::physics::skin_layer_stack(skin::physics::find_preset("caucasian").parameters, 550);
  const auto a = mc::simulate(stack, opts(12345, 7, 1));
  const auto b = mc::simulate(stack, opts(12345, 7, 2));
  const auto c = mc::simulate(stack, opts(12345, 7, 3));
  EXPECT_EQ(a.R_d, b.R_d);
  EXPECT_EQ(a.R_d_se, b.R_d_se);
  EXPECT_EQ(a.T_d, b.T_d);
  EXPECT_EQ(a.R, b.R);
  EXPECT_EQ(a.R_se, b.R_se);
  EXPECT_EQ(a.R, c.R);
  const auto d = mc::simulate(stack, opts(12345, 8, 2));
  EXPECT_NE(a.R_d, d.R_d);  // and the seed matters
}

// --- Against diffusion where diffusion is accurate -------------------------------------------

TEST(MonteCarloVsDiffusion, ThickHighAlbedoAgreesWithinAFewPercent) {
  // Semi-infinite, alpha' = 0.99 and a slab of 20 transport mean free paths: the regime where
  // the dipole / multipole is known to be accurate. Diffusion's own error there is ~1-3 %
  // (boundary treatment: polynomial F_dr, extrapolated boundary), so 4 % plus 4 sigma.
  for (const auto& s : {one_layer(0.01, 0.99, kInfinity, 1.0, 0.9),
                        one_layer(0.01, 0.99, kInfinity, 1.4, 0.9),
                        one_layer(0.01, 0.99, 20.0, 1.4, 0.9)}) {
    const auto r = mc::simulate(s, opts(20000));
    const double R_diff = skin::transport::DiffusionStack(s).R_d();
    EXPECT_NEAR(R_diff, r.R_d, 0.04 * r.R_d + 4 * r.R_d_se) << s << '\n' << r;
  }
}

// --- Input checking ------------------------------------------------------------------------

// --- The diffuse source from below and the exit histograms -----------------------------------

TEST(MonteCarloDiffuseSource, NonScatteringSlabTransmitsTwoE3) {
  // A Lambertian source under a purely absorbing, index-matched slab of optical depth tau: the
  // light crossing it is int_0^1 2 mu e^{-tau / mu} dmu = 2 E3(tau); none comes back.
  const double tau = 0.7;
  auto o = opts(100000);
  o.source = mc::Source::diffuse_bottom;
  const auto r = mc::simulate(one_layer(tau, 1e-12, 1.0, 1.0, 0.0), o);
  EXPECT_NEAR(r.R_d, 2 * boost::math::expint(3, tau), 4 * r.R_d_se + 1e-6) << r;
  EXPECT_NEAR(r.T_d, 0.0, 1e-9);
  EXPECT_EQ(r.R_specular, 0.0);
}

TEST(MonteCarloDiffuseSource, NonAbsorbingSlabConservesEnergyAndTotalInternalReflection) {
  // No absorption: everything leaves, up or down. With n = 1.4 under air and no scattering, the
  // light beyond the critical angle (1 - 1/n^2 of a Lambertian source) is reflected back down.
  auto o = opts(50000);
  o.source = mc::Source::diffuse_bottom;
  const auto a = mc::simulate(one_layer(0.0, 0.8, 0.5, 1.4, 0.9, 1.0, 1.4), o);
  EXPECT_NEAR(a.R_d + a.T_d, 1.0, 1e-9) << a;
  const auto b = mc::simulate(one_layer(0.0, 1e-12, 0.5, 1.4, 0.0, 1.0, 1.4), o);
  EXPECT_GT(b.T_d, 1 - 1 / (1.4 * 1.4)) << b;  // plus the Fresnel share below the critical angle
  EXPECT_LT(b.T_d, 1 - 1 / (1.4 * 1.4) + 0.1) << b;
  // A diffuse source needs a bottom to start on.
  EXPECT_THROW(mc::simulate(one_layer(0.1, 1, kInfinity, 1.4, 0.9), o), skin::util::InputError);
}

TEST(MonteCarloExitHistogram, SumsToTheTotalsAndHankelOfItIsTheTransform) {
  auto o = opts(20000);
  o.exit_bins = 300;
  o.exit_r_min = 1e-3;
  o.exit_r_max = 100;
  const auto r = mc::simulate(one_layer(0.2, 1.0, 1.0, 1.4, 0.9), o);
  ASSERT_EQ(r.exit_r_edges.size(), 301u);
  EXPECT_EQ(r.exit_r_edges[0], 0.0);
  EXPECT_NEAR(r.exit_r_edges[1], 1e-3, 1e-15);
  EXPECT_NEAR(r.exit_r_edges[300], 100, 1e-9);
  const double top = std::accumulate(r.top_exit.begin(), r.top_exit.end(), 0.0);
  const double bottom = std::accumulate(r.bottom_exit.begin(), r.bottom_exit.end(), 0.0);
  EXPECT_NEAR(top, r.R_d, 1e-3 * r.R_d);  // a few photons may leave beyond 100 mm
  EXPECT_NEAR(bottom, r.T_d, 1e-3 * r.T_d);
  EXPECT_NEAR(mc::hankel_transform(r.exit_r_edges, r.top_exit, 0.0), top, 1e-12);
  // The transform decays with frequency and is below its value at k = 0.
  EXPECT_LT(mc::hankel_transform(r.exit_r_edges, r.top_exit, 5.0), 0.5 * top);
}

TEST(MonteCarloExitHistogram, HankelTransformOfAUniformDiscIsExact) {
  // Weight spread uniformly over a disc of radius a: F(k) = 2 J1(k a) / (k a). A histogram whose
  // bins hold weights proportional to their areas is exactly that distribution.
  const double a = 2.0;
  std::vector<double> edges{0.0}, w;
  for (int i = 1; i <= 50; ++i) edges.push_back(a * std::pow(i / 50.0, 1.5));
  for (std::size_t i = 0; i + 1 < edges.size(); ++i)
    w.push_back((edges[i + 1] * edges[i + 1] - edges[i] * edges[i]) / (a * a));
  for (double k : {0.0, 1e-4, 0.3, 1.0, 7.0, 40.0}) {
    const double exact = k == 0 ? 1.0 : 2 * std::cyl_bessel_j(1.0, k * a) / (k * a);
    EXPECT_NEAR(mc::hankel_transform(edges, w, k), exact, 1e-9) << "k = " << k;
  }
}

TEST(MonteCarloInput, RejectsBadOptionsAndStacks) {
  const auto s = one_layer(0.1, 1.0, kInfinity, 1.4, 0.9);
  auto o = opts(100);
  o.photons = 0;
  EXPECT_THROW(mc::simulate(s, o), skin::util::InputError);
  o = opts(100);
  o.bins = 0;
  EXPECT_THROW(mc::simulate(s, o), skin::util::InputError);
  o = opts(100);
  o.r_max = -1;
  EXPECT_THROW(mc::simulate(s, o), skin::util::InputError);
  o = opts(100);
  o.r_max = std::nan("");
  EXPECT_THROW(mc::simulate(s, o), skin::util::InputError);
  o = opts(100, 1, -2);
  EXPECT_THROW(mc::simulate(s, o), skin::util::InputError);
  EXPECT_THROW(mc::simulate(LayerStack{}, opts(100)), skin::util::InputError);
  EXPECT_THROW(mc::simulate(one_layer(-1, 1, 1, 1.4, 0.9), opts(100)), skin::util::InputError);
  EXPECT_THROW(mc::simulate(one_layer(0.1, 1, 1, 1.4, 1.0), opts(100)), skin::util::InputError);
  o = opts(100);
  o.exit_bins = 1;
  EXPECT_THROW(mc::simulate(s, o), skin::util::InputError);
  o.exit_bins = 10;
  o.exit_r_max = o.exit_r_min;
  EXPECT_THROW(mc::simulate(s, o), skin::util::InputError);
}

}  // namespace
