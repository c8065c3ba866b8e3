// The Fresnel equations of a smooth dielectric interface (include/skin/physics/fresnel.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "skin/physics/fresnel.hpp"

namespace skin {

using skin::physics::FresnelResult;
using skin::physics::fresnel;
using skin::physics::fresnel_dielectric;

namespace {

TEST(Fresnel, NormalIncidenceIsTheSquaredIndexContrast) {
  // ((n1 - n2) / (n1 + n2))^2: 0.04 for glass (1.5), 0.0278 for skin (1.4); the same both ways.
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, 1.5), 0.04, 1e-15);
  EXPECT_NEAR(fresnel(1.0, 1.0, 1.4).R, (0.4 / 2.4) * (0.4 / 2.4), 1e-15);
  EXPECT_NEAR(fresnel(1.0, 1.4, 1.0).R, (0.4 / 2.4) * (0.4 / 2.4), 1e-15);
  EXPECT_EQ(fresnel(1.0, 1.0, 1.4).cos_t, 1.0);
  // A matched interface reflects nothing at any angle.
  for (double c : {1.0, 0.5, 0.01}) EXPECT_NEAR(fresnel_dielectric(c, 1.33, 1.33), 0.0, 1e-20) << c;
}

TEST(Fresnel, SnellsLawAndTotalInternalReflection) {
  for (double n1 : {1.0, 1.33, 1.4, 1.5}) {
    for (double n2 : {1.0, 1.4, 1.55}) {
      for (double c : {1.0, 0.9, 0.5, 0.2, 0.05}) {
        const FresnelResult f = fresnel(c, n1, n2);
        EXPECT_EQ(f.R, fresnel_dielectric(c, n1, n2));
        const double sin_i = std::sqrt(1 - c * c);
        if (n1 * sin_i < n2) {
          // Refracted: n1 sin_i = n2 sin_t, and R in [0, 1).
          EXPECT_NEAR(n1 * sin_i, n2 * std::sqrt(1 - f.cos_t * f.cos_t), 1e-12);
          EXPECT_GE(f.R, 0.0);
          EXPECT_LT(f.R, 1.0);
        } else {
          EXPECT_EQ(f.R, 1.0) << n1 << " -> " << n2 << " cos " << c;
          EXPECT_EQ(f.cos_t, 0.0);
        }
      }
    }
  }
  // Beyond the critical angle from 1.4 into air (cos_c = sqrt(1 - 1/1.96) = 0.700) and from 1.5.
  EXPECT_EQ(fresnel(0.6, 1.4, 1.0).R, 1.0);
  EXPECT_EQ(fresnel_dielectric(0.1, 1.5, 1.0), 1.0);
}

TEST(Fresnel, BrewsterAngleHasNoParallelReflection) {
  // At Brewster's angle tan theta_B = n2 / n1 the p-polarised reflection vanishes, so the
  // unpolarised R is half of r_s^2 = ((n1^2 - n2^2) / (n1^2 + n2^2))^2 there.
  const double n1 = 1.0, n2 = 1.5;
  const double c = std::cos(std::atan(n2 / n1));
  const double rs = (n1 * n1 - n2 * n2) / (n1 * n1 + n2 * n2);
  EXPECT_NEAR(fresnel_dielectric(c, n1, n2), 0.5 * rs * rs, 1e-15);
}

TEST(Fresnel, RoundedCosinePastOneCountsAsNormalIncidence) {
  const double past = std::nextafter(1.0, 2.0);
  const FresnelResult f = fresnel(past, 1.0, 1.4);
  EXPECT_EQ(f.cos_t, 1.0);
  EXPECT_NEAR(f.R, fresnel_dielectric(1.0, 1.0, 1.4), 1e-15);
}

}  // namespace
}  // namespace skin
