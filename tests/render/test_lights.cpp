// Lights (src/render/lights.hpp) through the interface the integrator uses: each sampler against
// its pdf by chi-square (fixed seeds; rejected at the 1e-3 significance level), each pdf
// integrating to one over the sphere by brute force, its support having the light's solid angle
// in closed form, and sample and pdf agreeing on every sampled direction.
#include <gtest/gtest.h>

#include <cmath>

#include "lights.hpp"
#include "sampler_checks.hpp"
#include "scene_data.hpp"

namespace skin::render {
namespace {
using namespace test;  // NOLINT(google-build-using-namespace)

// Integral of f over the sphere of directions by the midpoint rule in (cos theta, phi), fine
// enough that the outline of a light crossing the cells costs less than 1e-3.
double sphere_integral(const std::function<double(const Vec3&)>& f, int n_cos = 1000, int n_phi = 2000) {
  double s = 0;
  for (int i = 0; i < n_cos; ++i) {
    const double c = -1 + 2 * (i + 0.5) / n_cos, st = std::sqrt(std::max(0.0, 1 - c * c));
    for (int j = 0; j < n_phi; ++j) {
      const double ph = 2 * kPi * (j + 0.5) / n_phi;
      s += f({st * std::cos(ph), st * std::sin(ph), c});
    }
  }
  return s * (2.0 / n_cos) * (2 * kPi / n_phi);
}

// Draws n samples of `light` from p and checks, for each, that `pdf` returns the sampler's own
// density and that an area light is really there: the ray toward it hits at the sample's distance.
void expect_sample_matches_pdf(const Light& light, const Vec3& p, const Vec3& n, std::uint64_t seed) {
  SCOPED_TRACE(::testing::Message() << light << " seen from " << p);
  Rng rng(seed, 1);
  int ok = 0;
  for (int k = 0; k < 2000; ++k) {
    const LightSample ls = light.sample(p, n, {rng.uniform(), rng.uniform()});
    if (!(ls.pdf > 0)) continue;
    ++ok;
    EXPECT_NEAR(light.pdf(p, n, ls.wi), ls.pdf, 1e-9 * ls.pdf) << "wi " << ls.wi;
    double t = 0;
    ASSERT_TRUE(light.intersect(p, ls.wi, &t)) << "wi " << ls.wi;
    EXPECT_NEAR(t, ls.dist, 1e-9 * ls.dist);
    EXPECT_EQ(ls.L, light.Le());
  }
  EXPECT_GT(ok, 1000);
}

TEST(Lights, PointAndDirectionalAreDeltas) {
  // A delta light has no density over directions (no BSDF-sampled ray can hit it): pdf is 0
  // everywhere, and its one sample is exact whatever the random numbers (pdf 1 = the light).
  const Light point(PointLight{{1, 2, 3}, {4, 5, 6}});
  const Light sun(DirectionalLight{normalize(Vec3{0, -1, -1}), {2, 2, 2}});
  const Vec3 p{1, 2, 1}, n{0, 0, 1};
  for (Vec2 u : {Vec2{0.1, 0.9}, Vec2{0.7, 0.3}}) {
    const LightSample a = point.sample(p, n, u);
    EXPECT_TRUE(a.delta);
    EXPECT_EQ(a.pdf, 1.0);
    EXPECT_EQ(a.wi, (Vec3{0, 0, 1}));
    EXPECT_DOUBLE_EQ(a.dist, 2.0);
    EXPECT_EQ(a.L, (Rgb3{1, 1.25, 1.5}));  // intensity / d^2
    const LightSample b = sun.sample(p, n, u);
    EXPECT_TRUE(b.delta);
    EXPECT_EQ(b.pdf, 1.0);
    EXPECT_EQ(b.wi, normalize(Vec3{0, 1, 1}));
    EXPECT_TRUE(std::isinf(b.dist));
    EXPECT_EQ(b.L, (Rgb3{2, 2, 2}));
  }
  double t = 0;
  EXPECT_FALSE(point.intersect(p, {0, 0, 1}, &t));
  EXPECT_FALSE(sun.intersect(p, normalize(Vec3{0, 1, 1}), &t));
  EXPECT_EQ(sphere_integral([&](const Vec3& w) { return point.pdf(p, n, w) + sun.pdf(p, n, w); }, 50, 100), 0.0);
}

TEST(Lights, SphereSamplesItsPdf) {
  // From distance d the sphere fills a cone of cos theta_max = sqrt(1 - (R/d)^2), solid angle
  // 2 pi (1 - cos theta_max); the pdf is uniform over it and integrates to one.
  const SphereLight shape{{0.3, -0.2, 0.5}, 1.0, {3, 3, 3}};
  const Light light(shape);
  for (double d : {1.5, 4.0}) {
    SCOPED_TRACE(d);
    const Vec3 p = shape.centre + normalize(Vec3{0.4, 0.1, -0.9}) * d, n{0, 0, 1};
    double pv = 0, integral = 0;
    direction_chi_square([&](Vec2 u, Vec3* w) { const LightSample ls = light.sample(p, n, u); *w = ls.wi; return ls.pdf > 0; },
                         [&](const Vec3& w) { return light.pdf(p, n, w); }, 21, &pv, &integral, 24);
    EXPECT_GT(pv, 1e-3);
    EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return light.pdf(p, n, w); }), 1.0, 1e-3);
    const double cos_max = std::sqrt(1 - 1 / (d * d));
    EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return light.pdf(p, n, w) > 0 ? 1.0 : 0.0; }),
                2 * kPi * (1 - cos_max), 2e-3);
    expect_sample_matches_pdf(light, p, n, 22);
  }
  // From inside the light there is neither a sample nor a density.
  EXPECT_EQ(light.sample(shape.centre, {0, 0, 1}, {0.5, 0.5}).pdf, 0.0);
  EXPECT_EQ(light.pdf(shape.centre, {0, 0, 1}, {0, 0, 1}), 0.0);
}

TEST(Lights, QuadSamplesItsPdf) {
  // A 2 x 1.2 rectangle emitting toward -z seen from 0.8 below its centre: solid angle
  // 4 arcsin(a b / sqrt((a^2 + 4 h^2)(b^2 + 4 h^2))); the pdf integrates to one over it. From an
  // off-centre point the chi-square tests the area-to-solid-angle conversion where it varies most.
  const QuadLight shape{{-1, -0.6, 0.8}, {0, 1.2, 0}, {2, 0, 0}, {5, 5, 5}};
  ASSERT_NEAR(shape.normal().z, -1.0, 1e-15);
  const Light light(shape);
  const Vec3 n{0, 0, 1};
  {
    const Vec3 p{0, 0, 0};
    const double a = 2, b = 1.2, h = 0.8;
    EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return light.pdf(p, n, w) > 0 ? 1.0 : 0.0; }),
                4 * std::asin(a * b / std::sqrt((a * a + 4 * h * h) * (b * b + 4 * h * h))), 2e-3);
    EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return light.pdf(p, n, w); }), 1.0, 2e-3);
  }
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{1.4, 0.9, 0.3}}) {
    SCOPED_TRACE(::testing::Message() << "p " << p);
    double pv = 0, integral = 0;
    direction_chi_square([&](Vec2 u, Vec3* w) { const LightSample ls = light.sample(p, n, u); *w = ls.wi; return ls.pdf > 0; },
                         [&](const Vec3& w) { return light.pdf(p, n, w); }, 23, &pv, &integral, 24);
    EXPECT_GT(pv, 1e-3);
    EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return light.pdf(p, n, w); }), 1.0, 2e-3);
    expect_sample_matches_pdf(light, p, n, 24);
  }
  // Behind the emitting side: no sample, no density.
  const Vec3 behind{0, 0, 1.5};
  EXPECT_EQ(light.sample(behind, n, {0.5, 0.5}).pdf, 0.0);
  EXPECT_EQ(sphere_integral([&](const Vec3& w) { return light.pdf(behind, n, w); }, 100, 200), 0.0);
}

TEST(Lights, ChiSquareDetectsAWrongLightPdf) {
  // The test must be able to fail: directions sampled toward a sphere of radius 1.05 checked
  // against the pdf of radius 1 (a 5 % error in radius) are rejected.
  const Light right(SphereLight{{0, 0, 0}, 1.0, {1, 1, 1}}), wrong(SphereLight{{0, 0, 0}, 1.05, {1, 1, 1}});
  const Vec3 p{0, 0, -2}, n{0, 0, 1};
  double pv = 0, integral = 0;
  direction_chi_square([&](Vec2 u, Vec3* w) { const LightSample ls = wrong.sample(p, n, u); *w = ls.wi; return ls.pdf > 0; },
                       [&](const Vec3& w) { return right.pdf(p, n, w); }, 21, &pv, &integral, 24);
  EXPECT_LT(pv, 1e-3);
}

TEST(Lights, ConstantEnvironmentSamplesItsPdf) {
  // Cosine-weighted about the receiver's normal: the density integrates to one over its
  // hemisphere, and sample and pdf agree.
  Environment env;
  env.constant = {0.5, 0.5, 0.5};
  const Vec3 p{0, 0, 0}, n = normalize(Vec3{0.3, -0.4, 0.8});
  double pv = 0, integral = 0;
  direction_chi_square([&](Vec2 u, Vec3* w) { const LightSample ls = env.sample(p, n, u); *w = ls.wi; return ls.pdf > 0; },
                       [&](const Vec3& w) { return env.pdf(p, n, w); }, 16, &pv, &integral);
  EXPECT_GT(pv, 1e-3);
  EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return env.pdf(p, n, w); }), 1.0, 1e-4);
  Rng rng(17, 1);
  for (int k = 0; k < 100; ++k) {
    const LightSample ls = env.sample(p, n, {rng.uniform(), rng.uniform()});
    EXPECT_NEAR(env.pdf(p, n, ls.wi), ls.pdf, 1e-12);
    EXPECT_EQ(ls.L, env.constant);
  }
}

TEST(Lights, EnvironmentMapSamplesItsPdf) {
  // A 16 x 8 map with one bright texel and a gradient: the sampled directions must follow
  // pdf(dir), and pdf must integrate to one over the sphere.
  auto tex = std::make_shared<Texture>();
  tex->width = 16;
  tex->height = 8;
  tex->rgb.resize(16 * 8 * 3);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) tex->rgb[static_cast<std::size_t>((y * 16 + x) * 3 + c)] = static_cast<float>(0.1 + 0.05 * x + (x == 5 && y == 2 ? 20 : 0));
  Environment env;
  env.map = tex;
  env.rotation_deg = 30;
  env.build_distribution();
  const Vec3 p{0, 0, 0}, n{0, 0, 1};
  double pv = 0, integral = 0;
  direction_chi_square([&](Vec2 u, Vec3* w) { const LightSample ls = env.sample(p, n, u); *w = ls.wi; return ls.pdf > 0; },
                       [&](const Vec3& w) { return env.pdf(p, n, w); }, 15, &pv, &integral);
  EXPECT_GT(pv, 1e-3);
  // The texel edges are lines of constant theta and phi: the fine midpoint rule resolves them.
  EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return env.pdf(p, n, w); }), 1.0, 2e-3);
  Rng rng(18, 1);
  for (int k = 0; k < 200; ++k) {
    const LightSample ls = env.sample(p, n, {rng.uniform(), rng.uniform()});
    if (!(ls.pdf > 0)) continue;
    // The direction maps back to the texel it was drawn in, except on a texel edge.
    EXPECT_NEAR(env.pdf(p, n, ls.wi), ls.pdf, 1e-9 * ls.pdf) << ls.wi;
    EXPECT_EQ(ls.L, env.radiance(ls.wi));
  }
}

}  // namespace
}  // namespace skin::render
