// One-layer diffusion: closed forms against brute-force numerics and known limits.
#include <gtest/gtest.h>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <numbers>

#include "skin/transport/diffusion.hpp"
#include "skin/transport/stack.hpp"

using namespace skin;
using skin::transport::A_boundary;
using skin::transport::DiffusionSlab;
using skin::transport::F_dr;
using skin::transport::F_dr_exact;
using skin::transport::R_d_semi_infinite;
using skin::physics::kInfinity;

namespace {
// Brute-force 2D Fourier (Hankel order 0) transform of a spatial profile:
// 2 pi int_0^inf f(r) J0(k r) r dr, adaptive Gauss-Kronrod on consecutive intervals until the
// integrand is negligible.
template <class F>
double hankel_numeric(F f, double k, double r_end) {
  using GK = boost::math::quadrature::gauss_kronrod<double, 61>;
  double sum = 0.0;
  // Short panels near 0 where the profile is peaked, then wider ones.
  double a = 0.0;
  double h = 1e-3;
  while (a < r_end) {
    const double b = std::min(a + h, r_end);
    sum += GK::integrate([&](double r) { return f(r) * ::j0(k * r) * r; }, a, b, 6, 1e-10);
    a = b;
    h = std::min(h * 1.5, k > 0 ? 0.5 / k : 1.0);
  }
  return 2.0 * std::numbers::pi * sum;
}

struct SlabCase {
  double sigma_a, sigma_s_prime, d, eta_top, eta_bottom;
};
std::ostream& operator<<(std::ostream& os, const SlabCase& c) {
  return os << "SlabCase{sigma_a=" << c.sigma_a << ", sigma_s_prime=" << c.sigma_s_prime
            << ", d=" << c.d << ", eta_top=" << c.eta_top << ", eta_bottom=" << c.eta_bottom << '}';
}
DiffusionSlab slab(const SlabCase& c) {
  return DiffusionSlab::make(c.sigma_a, c.sigma_s_prime, c.d, A_boundary(c.eta_top),
                             A_boundary(c.eta_bottom));
}
}  // namespace

class SlabTest : public ::testing::TestWithParam<SlabCase> {};

// The closed-form geometric sums of the frequency-domain image series against the explicit
// image-pair sum (which is what DJ05 writes down).
TEST_P(SlabTest, ClosedFormFrequencyDomainEqualsExplicitImageSum) {
  const DiffusionSlab s = slab(GetParam());
  for (double k : {0.0, 0.3, 2.0, 15.0}) {
    // Tolerance: the explicit sum stops when a pair changes it by < 1e-13 relative; its tail is
    // then below ~1e-10 even for the slowly converging weakly absorbing cases.
    EXPECT_NEAR(s.R_k(k), s.R_k_sum(k, 1e-13), 1e-9 * std::abs(s.R_k(k)) + 1e-14) << s << " k=" << k;
    EXPECT_NEAR(s.T_k(k), s.T_k_sum(k, 1e-13), 1e-9 * std::abs(s.T_k(k)) + 1e-14) << s << " k=" << k;
  }
}

// The closed-form transform of each pole (model-notes section 4) against a brute-force numerical
// Hankel transform of the spatial image sum, for the slabs whose exp(-sigma_tr r) tail ends
// within 125 mm (the nearly non-absorbing one, sigma_tr = 0.055/mm, would take minutes; the
// explicit image sum and energy conservation cover it).
class AbsorbingSlabTest : public SlabTest {};
TEST_P(AbsorbingSlabTest, FrequencyDomainEqualsNumericalHankelTransformOfSpatialProfile) {
  const DiffusionSlab s = slab(GetParam());
  ASSERT_GE(s.sigma_tr, 0.2) << s;
  // Integrate far enough that the exp(-sigma_tr r) tail is below the tolerance.
  const double r_end = 25.0 / s.sigma_tr;
  for (double k : {0.0, 1.0, 5.0}) {
    const double R_num = hankel_numeric([&](double r) { return s.R(r, 1e-11); }, k, r_end);
    const double T_num = hankel_numeric([&](double r) { return s.T(r, 1e-11); }, k, r_end);
    // 1e-4 relative: the numerical integral's own accuracy (tail beyond r_end, quadrature).
    EXPECT_NEAR(R_num, s.R_k(k), 1e-4 * std::abs(s.R_k(k)) + 1e-7) << s << " k=" << k;
    EXPECT_NEAR(T_num, s.T_k(k), 1e-4 * std::abs(s.T_k(k)) + 1e-7) << s << " k=" << k;
  }
}

const SlabCase kAbsorbingSlabs[] = {
    SlabCase{0.1, 10.0, 1.0, 1.4, 1.4},  // thick-ish, mismatched both sides
    SlabCase{0.5, 5.0, 0.25, 1.4, 1.0},  // epidermis-like over matched
    SlabCase{0.05, 2.0, 2.0, 1.3, 1.5},  // weakly absorbing, asymmetric boundaries
    SlabCase{1.0, 20.0, 0.1, 1.0, 1.0},  // matched, thin
};
INSTANTIATE_TEST_SUITE_P(Slabs, AbsorbingSlabTest, ::testing::ValuesIn(kAbsorbingSlabs));
INSTANTIATE_TEST_SUITE_P(Slabs, SlabTest,
                         ::testing::Values(kAbsorbingSlabs[0], kAbsorbingSlabs[1], kAbsorbingSlabs[2],
                                           kAbsorbingSlabs[3],
                                           SlabCase{0.001, 1.0, 0.5, 1.4, 1.4}));  // nearly non-absorbing, thin

TEST(Dipole, TotalEqualsClassicClosedForm) {
  // R_d = R(k = 0) from the two poles must equal Jensen et al. 2001's closed form exactly.
  for (double eta : {1.0, 1.3, 1.4, 1.5}) {
    for (double alpha : {0.1, 0.5, 0.9, 0.99, 0.9999}) {
      const double sigma_s_prime = 2.0, sigma_a = sigma_s_prime * (1 - alpha) / alpha;
      const DiffusionSlab s = DiffusionSlab::make(sigma_a, sigma_s_prime, kInfinity, A_boundary(eta), 1.0);
      EXPECT_NEAR(s.R_d(), R_d_semi_infinite(s.alpha_prime, A_boundary(eta)), 1e-13)
          << "eta=" << eta << " alpha'=" << alpha;
    }
  }
}

TEST(Dipole, SpatialProfileIntegratesToTotal) {
  const DiffusionSlab s = DiffusionSlab::make(0.05, 3.0, kInfinity, A_boundary(1.4), 1.0);
  const double R_num = hankel_numeric([&](double r) { return s.R(r); }, 0.0, 200.0);
  EXPECT_NEAR(R_num, s.R_d(), 1e-5 * s.R_d());
}

TEST(Multipole, NonAbsorbingSlabConservesEnergy) {
  // With sigma_a -> 0 every photon leaves through the top or the bottom: R_d + T_d -> 1. The
  // closed form sums all image pairs; the explicit sum needs very many pairs as sigma_tr -> 0.
  // Slabs thicker than the source depth z_r = 1 / sigma_t' = 0.5 mm: below that the real source lies
  // outside the slab and the multipole is outside its validity (the CLI warns of the negative T).
  for (double d : {0.6, 2.0, 10.0}) {
    for (double eta : {1.0, 1.4}) {
      double previous_gap = 1.0;
      for (double sigma_a : {1e-2, 1e-4, 1e-6, 1e-8}) {
        const DiffusionSlab s = DiffusionSlab::make(sigma_a, 2.0, d, A_boundary(eta), A_boundary(eta));
        const double gap = std::abs(1.0 - s.R_d() - s.T_d());
        EXPECT_LT(gap, previous_gap + 1e-12) << s;  // converges monotonically
        previous_gap = gap;
      }
      // At sigma_a = 1e-8 the loss is of the order of sigma_a times the mean path length.
      EXPECT_LT(previous_gap, 1e-5) << "d=" << d << " eta=" << eta;
      const DiffusionSlab s = DiffusionSlab::make(1e-8, 2.0, d, A_boundary(eta), A_boundary(eta));
      // Truncated explicit sums with enough pairs reach the same totals.
      EXPECT_NEAR(s.R_k_sum(0.0, 1e-14, 2000000) + s.T_k_sum(0.0, 1e-14, 2000000), 1.0, 2e-4);
    }
  }
}

TEST(Multipole, ThickSlabTendsToDipole) {
  const DiffusionSlab thick = DiffusionSlab::make(0.1, 5.0, 100.0, A_boundary(1.4), 1.0);
  const DiffusionSlab semi = DiffusionSlab::make(0.1, 5.0, kInfinity, A_boundary(1.4), 1.0);
  EXPECT_NEAR(thick.R_d(), semi.R_d(), 1e-12);
  EXPECT_NEAR(thick.R(0.5), semi.R(0.5), 1e-10);
  EXPECT_LT(thick.T_d(), 1e-20);
}

TEST(Multipole, FlippedSlabSwapsBoundaries) {
  const DiffusionSlab s = DiffusionSlab::make(0.2, 4.0, 0.3, A_boundary(1.4), 1.0);
  const DiffusionSlab f = s.flipped();
  EXPECT_EQ(f.A_top, s.A_bottom);
  EXPECT_EQ(f.A_bottom, s.A_top);
  // A slab with the same boundary on both sides looks the same from both sides.
  const DiffusionSlab sym = DiffusionSlab::make(0.2, 4.0, 0.3, A_boundary(1.4), A_boundary(1.4));
  EXPECT_NEAR(sym.R_k(1.0), sym.flipped().R_k(1.0), 1e-15);
  // Mismatched on top only: reflectance from below differs (the reason the stack computes it).
  EXPECT_GT(std::abs(s.R_d() - f.R_d()), 1e-3);
}

TEST(Fresnel, PolynomialFitAgreesWithExactIntegral) {
  // The Egan-Hilgeman fit is quoted as accurate to about 1 % in the range of tissue indices.
  for (double eta : {1.2, 1.33, 1.4, 1.5}) EXPECT_NEAR(F_dr(eta), F_dr_exact(eta), 0.01) << eta;
  // Exact limits: matched boundary reflects nothing.
  EXPECT_EQ(F_dr(1.0), 0.0);
  EXPECT_NEAR(F_dr_exact(1.0 + 1e-9), 0.0, 1e-6);
}

TEST_P(SlabTest, CombinedTransferEqualsSeparateCalls) {
  const DiffusionSlab s = slab(GetParam());
  const DiffusionSlab f = s.flipped();
  for (double k : {0.0, 1e-4, 0.3, 2.0, 15.0, 200.0}) {
    const auto t = s.transfer_k(k);
    const double tol = 1e-12;
    EXPECT_NEAR(t[0], s.R_k(k), tol) << s << " k=" << k;
    EXPECT_NEAR(t[1], s.T_k(k), tol) << s << " k=" << k;
    EXPECT_NEAR(t[2], f.R_k(k), tol) << s << " k=" << k;
    EXPECT_NEAR(t[3], f.T_k(k), tol) << s << " k=" << k;
  }
}
