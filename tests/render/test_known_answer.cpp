// End-to-end renders with answers known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "skin/color/color.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/render/microfacet.hpp"
#include "scene_data.hpp"
#include <filesystem>
#include "skin/render/scene.hpp"

namespace skin::render {

using skin::model::SkinSpectrum;
using skin::model::skin_spectrum;


using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;
using skin::physics::kInfinity;

namespace {

struct Stats {
  Rgb3 mean, stderr_;  // mean over pixels and its standard error
};

Stats pixel_stats(const Image& img) {
  Rgb3 s, s2;
  const int n = img.width * img.height;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Rgb3 c = img.at(x, y);
      s += c;
      s2 += c * c;
    }
  Stats st;
  st.mean = s / n;
  for (int c = 0; c < 3; ++c)
    st.stderr_[c] = std::sqrt(std::max(0.0, s2[c] / n - st.mean[c] * st.mean[c]) / n);
  return st;
}

// A flat slab seen from straight above, filling the view, under a uniform environment of unit
// radiance; `material` is the JSON of the slab's material.
std::string slab_scene(const std::string& material, int depth = 1) {
  return R"({ "camera": {"eye":[0,100,0], "look_at":[0,0,0], "up":[0,0,-1], "fov": 10, "resolution":[64,64]},
  "materials": {"m": )" + material + R"(},
  "objects": [{"quad": {"corner":[-2000,0,2000], "edge_u":[4000,0,0], "edge_v":[0,0,-4000]}, "material":"m"}],
  "environment": {"radiance": 1}, "render": {"spp": 32, "max_depth": )" + std::to_string(depth) + "} }";
}

TEST(KnownAnswer, SkinSlabWithoutSpecularIsRdColour) {
  // With rho_s = 0 nothing is reflected at the surface, F_t = 1, and the subsurface term of a
  // semi-infinite flat slab under uniform unit radiance (white: D65 in white-balanced linear
  // sRGB) is L_o = (1/pi) int R(r) dA int cos dw = R_d: the pixel colour is the linear sRGB
  // colour of R_d, which `skin color` reports, for either solver of the model.
  for (const char* solver : {"accurate", "multipole"}) {
    SCOPED_TRACE(solver);
    const Scene scene = Scene::parse(
        slab_scene(std::string(R"({"type":"skin","preset":"caucasian","rho_s":0,"solver":")") + solver + "\"}"), "", "slab");
    RenderSettings rs;
    rs.seed = 7;
    const Stats st = pixel_stats(render(scene, rs));
    SkinParameters p = find_preset("caucasian").parameters;
    p.oiliness = 0;
    const auto expected = skin_spectrum(p, WavelengthGrid(), skin::transport::find_model(solver)).color.srgb_linear;
    for (int c = 0; c < 3; ++c) {
      SCOPED_TRACE(c);
      EXPECT_NEAR(st.mean[c], expected[c], 0.01 * expected[c]) << st.mean << " stderr " << st.stderr_;
    }
  }
}

// The colour of a rendered slab pixel mean (white-balanced linear sRGB, not adapted: what the
// renderer writes) as CIELAB relative to the white of `cm`'s illuminant: XYZ = the sRGB matrix
// inverse, times the D65 white the film balanced by.
color::Lab rendered_lab(const Rgb3& rgb, const color::Colorimetry& cm) {
  const color::Colorimetry d65{WavelengthGrid()};
  const Rgb3 white = color::xyz_to_srgb_linear(d65.d65_white());
  return color::xyz_to_lab(color::srgb_linear_to_xyz(rgb * white), cm.white());
}

TEST(KnownAnswer, SpectralAndRgbSlabsAgreeWithSkinColorUnderD65) {
  // The issue's check: a uniformly lit slab (rho_s = 0: the pixel is the colour of R_d) renders
  // to the colour `skin color` prints under D65, in RGB and in spectral rendering, within 1
  // CIEDE2000 for three presets. Spectral: the profiles on a 10 nm grid interpolated in
  // wavelength, the film integrating over 400-700 nm (skin color: the 2 nm grid); measured
  // differences are about 0.1 (docs/renderer.md).
  const color::Colorimetry d65{WavelengthGrid()};
  for (const char* preset : {"caucasian", "asian", "african"}) {
    SkinParameters p = find_preset(preset).parameters;
    p.oiliness = 0;
    const SkinSpectrum expected = skin_spectrum(p);
    for (const bool spectral : {false, true}) {
      SCOPED_TRACE(::testing::Message() << preset << (spectral ? " spectral" : " RGB"));
      SceneDescription description = SceneDescription::parse(
          slab_scene(std::string(R"({"type":"skin","rho_s":0,"preset":")") + preset + "\"}"), "", "slab");
      description.set_spectral(spectral);
      const Scene scene = description.build();
      RenderSettings rs;
      rs.seed = 11;
      rs.width = rs.height = 24;
      rs.spp = 16;
      const Stats st = pixel_stats(render(scene, rs));
      const double dE = color::delta_e_2000(rendered_lab(st.mean, d65), expected.color.lab);
      EXPECT_LT(dE, 1.0) << st.mean << " stderr " << st.stderr_ << " expected " << expected.color.srgb_linear;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(st.mean[c], expected.color.srgb_linear[c], 4 * st.stderr_[c] + 0.01 * expected.color.srgb_linear[c]);
    }
  }
}

TEST(KnownAnswer, SpectralSlabUnderIlluminantAIsSkinColorUnderA) {
  // Under an environment of illuminant A (luminance 1), the spectral render's XYZ is that of R_d
  // under A, which `skin color --illuminant A` prints (before its adaptation to D65): within 1
  // CIEDE2000 relative to A's white. The RGB render multiplies R_d's colour by A's colour
  // instead; it misses by more (docs/renderer.md), which this test does not assert.
  SkinParameters p = find_preset("caucasian").parameters;
  p.oiliness = 0;
  const color::Colorimetry a(WavelengthGrid(), color::find_illuminant("A"));
  const color::Lab expected = color::summarize(a, skin_spectrum(p).R_d).lab;
  std::string js = slab_scene(R"({"type":"skin","rho_s":0,"preset":"caucasian"})");
  const std::string white = R"("radiance": 1})";
  js.replace(js.find(white), white.size(), R"("radiance": 1, "illuminant": "A"})");
  SceneDescription description = SceneDescription::parse(js, "", "slab-A");
  description.set_spectral(true);
  const Scene scene = description.build();
  RenderSettings rs;
  rs.seed = 12;
  rs.width = rs.height = 24;
  rs.spp = 16;
  const Stats st = pixel_stats(render(scene, rs));
  EXPECT_LT(color::delta_e_2000(rendered_lab(st.mean, a), expected), 1.0) << st.mean << " stderr " << st.stderr_;
}

TEST(KnownAnswer, WhiteFurnaceFlatSlab) {
  // A non-absorbing semi-infinite medium reflects everything (R_d = 1 for alpha' = 1 in the
  // dipole and multipole, whatever the boundary mismatch); without a specular term F_t = 1, so
  // under uniform unit radiance every pixel is 1.
  const Scene scene = Scene::parse(slab_scene(R"({"type":"layered","layers":[{"sigma_a":0,"sigma_s_prime":10,"eta":1.4}]})", 4), "", "furnace");
  RenderSettings rs;
  rs.seed = 3;
  const Stats st = pixel_stats(render(scene, rs));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(st.mean[c], 1.0, 4 * st.stderr_[c] + 1e-3) << st.mean << " stderr " << st.stderr_;
}

TEST(KnownAnswer, WhiteFurnaceSphere) {
  // The same medium on a sphere of 300 mm radius (300 transport mean free paths): curvature
  // changes the area the profile sees by O(mfp / radius), and every exit direction sees the
  // uniform environment, so the sphere renders to 1 too. Exercises the probe rays on a curved
  // closed surface (both sides found, tangent probes through the body).
  const std::string js = R"({ "camera": {"eye":[0,0,2000], "look_at":[0,0,0], "fov": 6, "resolution":[48,48]},
    "materials": {"m": {"type":"layered","layers":[{"sigma_a":0,"sigma_s_prime":10}]}},
    "objects": [{"sphere": {"center":[0,0,0], "radius":300}, "material":"m"}],
    "environment": {"radiance": 1}, "render": {"spp": 16, "max_depth": 6} })";
  RenderSettings rs;
  rs.seed = 5;
  const Image img = render(Scene::parse(js, "", "furnace-sphere"), rs);
  // The central 16 x 16 pixels lie on the sphere.
  Image centre(16, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) centre.set(x, y, img.at(16 + x, 16 + y));
  const Stats st = pixel_stats(centre);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(st.mean[c], 1.0, 4 * st.stderr_[c] + 0.01) << st.mean << " stderr " << st.stderr_;
}

TEST(KnownAnswer, SkinSlabWithSpecularTerm) {
  // With the surface term, a flat slab under uniform unit radiance seen at theta_o has
  //   L_o = rho_dr(theta_o) + (1 - rho_dr(theta_o)) R_d (1 - rho_dr_mean),
  // rho_dr = rho_s x (eq 2 at rho_s = 1), rho_dr_mean its cosine-weighted hemispherical mean:
  // the surface reflects rho_dr, the subsurface term receives (1 - rho_dr(theta_i)) of the light
  // from each direction (mean 1 - rho_dr_mean), spreads it with total R_d, and lets out
  // (1 - rho_dr(theta_o)) of it toward the camera. Seen from straight above (theta_o < 5 deg).
  const Scene scene = Scene::parse(slab_scene(R"({"type":"skin","preset":"caucasian"})"), "", "slab");
  RenderSettings rs;
  rs.seed = 8;
  const Stats st = pixel_stats(render(scene, rs));
  const SkinParameters p = find_preset("caucasian").parameters;
  const SpecularAlbedo albedo(p.roughness, p.eta);
  const double rho_o = p.oiliness * albedo.rho_dr(1.0), rho_mean = p.oiliness * albedo.mean();
  const auto R_d = skin_spectrum(p).color.srgb_linear;
  for (int c = 0; c < 3; ++c) {
    const double expected = rho_o + (1 - rho_o) * R_d[c] * (1 - rho_mean);
    EXPECT_NEAR(st.mean[c], expected, 0.01 * expected) << st.mean << " stderr " << st.stderr_;
  }
}

TEST(KnownAnswer, DiffusePlaneUnderSphereAndPointLights) {
  // Irradiance under a sphere light of radius R and radiance L straight above at height h is
  // E = pi L (R / h)^2 (the light fills a cone of sin^2(theta_max) = (R / h)^2); a point light of
  // intensity I gives E = I / h^2. A diffuse plane of albedo a then has radiance a E / pi.
  const double h = 1000, R = 100, L = 5, I = 2e5, a = 0.6;
  for (int kind = 0; kind < 2; ++kind) {
    const std::string light = kind == 0
        ? R"({"type":"sphere","center":[0,1000,0],"radius":100,"radiance":5})"
        : R"({"type":"point","position":[0,1000,0],"intensity":200000})";
    const std::string js = R"({ "camera": {"eye":[0,10,0], "look_at":[0,0,0], "up":[0,0,-1], "fov": 2, "resolution":[32,32]},
      "materials": {"m": {"type":"diffuse","albedo":0.6}},
      "objects": [{"quad": {"corner":[-50,0,50], "edge_u":[100,0,0], "edge_v":[0,0,-100]}, "material":"m"}],
      "lights": [)" + light + R"(], "render": {"spp": 16, "max_depth": 1} })";
    RenderSettings rs;
    rs.seed = 9;
    const Stats st = pixel_stats(render(Scene::parse(js, "", "plane"), rs));
    const double E = kind == 0 ? kPi * L * (R / h) * (R / h) : I / (h * h);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(st.mean[c], a * E / kPi, 4 * st.stderr_[c] + 1e-3 * a * E / kPi) << "light " << kind;
  }
}

TEST(Determinism, SameImageWithOneAndTwoThreads) {
  const std::string js = R"({ "camera": {"eye":[0,20,120], "look_at":[0,0,0], "fov": 30, "resolution":[40,30]},
    "materials": {"s": {"type":"skin","preset":"asian"}, "d": {"type":"diffuse","albedo":0.4}},
    "objects": [{"sphere": {"center":[0,0,0], "radius":20}, "material":"s"},
                {"quad": {"corner":[-100,-20,100], "edge_u":[200,0,0], "edge_v":[0,0,-200]}, "material":"d"}],
    "lights": [{"type":"sphere","center":[-50,80,60],"radius":10,"radiance":20},
               {"type":"quad","corner":[20,60,-40],"edge_u":[20,0,0],"edge_v":[0,0,20],"radiance":[3,3,3]}],
    "environment": {"radiance": 0.1}, "render": {"spp": 4, "max_depth": 4} })";
  const Scene scene = Scene::parse(js, "", "determinism");
  RenderSettings one, two;
  one.threads = 1;
  two.threads = 2;
  one.seed = two.seed = 1234;
  const Image a = render(scene, one), b = render(scene, two);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_TRUE(a.rgb == b.rgb);
  RenderSettings other = two;
  other.seed = 1235;
  EXPECT_FALSE(render(scene, other).rgb == a.rgb);  // the seed matters
}

TEST(Determinism, SpectralSameImageWithOneAndTwoThreads) {
  const std::string js = R"({ "camera": {"eye":[0,20,120], "look_at":[0,0,0], "fov": 30, "resolution":[24,16]},
    "materials": {"s": {"type":"skin","preset":"asian"}, "d": {"type":"diffuse","albedo":[0.6,0.4,0.2]}},
    "objects": [{"sphere": {"center":[0,0,0], "radius":20}, "material":"s"},
                {"quad": {"corner":[-100,-20,100], "edge_u":[200,0,0], "edge_v":[0,0,-200]}, "material":"d"}],
    "lights": [{"type":"sphere","center":[-50,80,60],"radius":10,"radiance":20,"illuminant":"A"}],
    "environment": {"radiance": 0.1}, "render": {"spp": 2, "max_depth": 3, "spectral": true} })";
  const Scene scene = Scene::parse(js, "", "determinism-spectral");
  ASSERT_TRUE(scene.spectral());
  RenderSettings one, two;
  one.threads = 1;
  two.threads = 2;
  one.seed = two.seed = 99;
  const Image a = render(scene, one), b = render(scene, two);
  EXPECT_TRUE(a.rgb == b.rgb);
}


TEST(KnownAnswer, ThinSlabLitFromBehindShowsTranslucency) {
  // A slab of skin 1 mm thick, lit only from behind by unit radiance over the back hemisphere
  // (an environment map bright for z < 0, black for z > 0), seen from the front. With rho_s = 0
  // every point of the back face receives E = pi and lets in all of it; the front face receives
  // nothing directly. The diffusion profile connects a front point to back points at distance
  // sqrt(s^2 + t^2) >= t, so the front radiance is the profile's tail beyond t:
  //   L_front = 2 pi int_t^inf R(rho) rho drho
  // (the semi-infinite profile applied across the slab, which is what the probe rays do).
  const double t = 1.0;
  const auto dir = std::filesystem::temp_directory_path() / ("skin_thin_slab_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  Image env(64, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      // u = phi / 2 pi with phi = atan2(x, -z): |phi| < 90 deg (u < 1/4 or u > 3/4) is z < 0.
      const double u = (x + 0.5) / 64;
      const double v = (u < 0.25 || u > 0.75) ? 1.0 : 0.0;
      env.set(x, y, {v, v, v});
    }
  write_image((dir / "back.exr").string(), env);
  const std::string js = R"({ "camera": {"eye":[0,0,100], "look_at":[0,0,0], "fov": 4, "resolution":[48,48]},
    "materials": {"m": {"type":"skin","preset":"caucasian","rho_s":0}},
    "objects": [{"quad": {"corner":[-500,-500,0], "edge_u":[1000,0,0], "edge_v":[0,1000,0]}, "material":"m"},
                {"quad": {"corner":[-500,-500,-1], "edge_u":[0,1000,0], "edge_v":[1000,0,0]}, "material":"m"}],
    "environment": {"map": "back.exr"}, "render": {"spp": 32, "max_depth": 1} })";
  RenderSettings rs;
  rs.seed = 21;
  const Stats st = pixel_stats(render(Scene::parse(js, dir.string(), "thin-slab"), rs));
  std::filesystem::remove_all(dir);
  SkinParameters p = find_preset("caucasian").parameters;
  p.oiliness = 0;
  const TranslucentMaterial m = build_translucent(skin_description(p));
  for (int c = 0; c < 3; ++c) {
    const TabulatedProfile& prof = m.profile[static_cast<std::size_t>(c)];
    // Tail integral by the midpoint rule on a fine log grid from t to r_max.
    double tail = 0;
    constexpr int kN = 20000;
    for (int i = 0; i < kN; ++i) {
      const double a = t * std::pow(prof.r_max() / t, static_cast<double>(i) / kN);
      const double b = t * std::pow(prof.r_max() / t, static_cast<double>(i + 1) / kN);
      const double mid = 0.5 * (a + b);
      tail += 2 * kPi * prof.eval(mid) * mid * (b - a);
    }
    SCOPED_TRACE(::testing::Message() << "channel " << c << " expected " << tail);
    EXPECT_GT(tail, 0.0);
    EXPECT_NEAR(st.mean[c], tail, 4 * st.stderr_[c] + 0.02 * tail) << st.mean << " stderr " << st.stderr_;
  }
  // Red light crosses the slab best (least absorbed, longest profile): the back-lit colour is red.
  EXPECT_GT(st.mean.r, 2 * st.mean.b);
}


TEST(KnownAnswer, ParameterMapBlendsNodeProfiles) {
  // A C_m map of constant value 0.25 over [0.002, 0.042] with 3 levels (nodes 0.002, 0.022,
  // 0.042) lies halfway between the first two nodes: each shading point uses one of them with
  // probability 1/2, so the slab renders to the mean of their R_d colours.
  const auto dir = std::filesystem::temp_directory_path() / ("skin_param_map_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  Image map(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) map.set(x, y, {0.25, 0.25, 0.25});
  write_image((dir / "cm.exr").string(), map);
  const std::string material = R"({"type":"skin","preset":"caucasian","rho_s":0,
      "parameter_maps": {"C_m": {"texture": "cm.exr", "channel": "R", "min": 0.002, "max": 0.042, "levels": 3}}})";
  RenderSettings rs;
  rs.seed = 17;
  const Stats st = pixel_stats(render(Scene::parse(slab_scene(material), dir.string(), "map"), rs));
  std::filesystem::remove_all(dir);
  SkinParameters a = find_preset("caucasian").parameters, b = a;
  a.oiliness = b.oiliness = 0;
  a.melanin = 0.002;
  b.melanin = 0.022;
  const auto ca = skin_spectrum(a).color.srgb_linear, cb = skin_spectrum(b).color.srgb_linear;
  for (int c = 0; c < 3; ++c) {
    const double expected = 0.5 * (ca[c] + cb[c]);
    EXPECT_NEAR(st.mean[c], expected, 0.015 * expected) << st.mean << " stderr " << st.stderr_;
  }
}

TEST(KnownAnswer, CreaseNeitherDarkNorBright) {
  // A concave right-angle crease (floor y = 0, z >= 0 and wall z = 0, y >= 0, crease along x)
  // of an absorbing layered medium, lit by a directional light along the bisector, so that both
  // faces receive E cos 45 deg everywhere and nothing is in shadow. With rho_s = 0 and direct
  // light only, a floor point at distance d from the crease has radiance
  //   L(d) = (1/pi) E cos45 [ int_floor R(|x_o - y|) dA + int_wall R(|x_o - y|) dA ],
  // both integrals over the actual (folded) surface, which the probe rays must find: the normal
  // probe mostly the floor, the tangent probes the wall. Reduced to line integrals of the
  // profile, g(a) = int R(sqrt(u^2 + a^2)) du:
  //   floor: int_{-d}^{inf} g(|t|) dt,   wall: int_0^inf g(sqrt(v^2 + d^2)) dv.
  // A probe axis missed or counted twice would make the rows near the crease dark or bright.
  const std::string js = R"({ "camera": {"eye":[0,2000,2000], "look_at":[0,0,0], "up":[0,1,-1], "fov": 0.3, "resolution":[24,48]},
    "materials": {"m": {"type":"layered","layers":[{"sigma_a":0.2,"sigma_s_prime":2}]}},
    "objects": [{"quad": {"corner":[-500,0,500], "edge_u":[1000,0,0], "edge_v":[0,0,-500]}, "material":"m"},
                {"quad": {"corner":[-500,0,0], "edge_u":[1000,0,0], "edge_v":[0,500,0]}, "material":"m"}],
    "lights": [{"type":"directional","direction":[0,-1,-1],"irradiance":1}],
    "render": {"spp": 256, "max_depth": 1} })";
  RenderSettings rs;
  rs.seed = 31;
  const Image img = render(Scene::parse(js, "", "crease"), rs);
  std::array<LayerStack, 3> stacks;
  for (auto& st : stacks) st.layers.push_back(Layer{0.2, 2.0, kInfinity, 1.4, 0.9});
  const TranslucentMaterial m = build_translucent(layered_description(stacks));
  const TabulatedProfile& R = m.profile[0];
  const auto g = [&](double a) {  // 2 int_0^inf R(sqrt(u^2 + a^2)) du, midpoint in log-ish steps
    double s = 0;
    const double u_max = R.r_max();
    constexpr int kN = 400;
    for (int i = 0; i < kN; ++i) {
      const double u0 = u_max * std::pow(static_cast<double>(i) / kN, 2), u1 = u_max * std::pow(static_cast<double>(i + 1) / kN, 2);
      s += R.eval(std::sqrt(0.25 * (u0 + u1) * (u0 + u1) + a * a)) * (u1 - u0);
    }
    return 2 * s;
  };
  const auto line = [&](const std::function<double(double)>& f, double a, double b) {
    double s = 0;
    constexpr int kN = 400;
    for (int i = 0; i < kN; ++i) {
      const double t0 = a + (b - a) * std::pow(static_cast<double>(i) / kN, 2), t1 = a + (b - a) * std::pow(static_cast<double>(i + 1) / kN, 2);
      s += f(0.5 * (t0 + t1)) * (t1 - t0);
    }
    return s;
  };
  // Camera on the bisector 2828 mm away: image row y (of 48) sees the floor (lower half) at
  // distance d = sqrt(2) |s| from the crease, s the row's offset in the image plane.
  const double half = 2828.43 * std::tan(0.15 * kPi / 180);
  for (int y : {24, 25, 26, 28, 32, 40, 47}) {
    const double s = (2.0 * (y + 0.5) / 48 - 1) * half;
    const double d = std::sqrt(2.0) * s;
    const double floor_part = line([&](double t) { return g(std::abs(t)); }, -d, 0) + line([&](double t) { return g(t); }, 0, R.r_max());
    const double wall_part = line([&](double v) { return g(std::sqrt(v * v + d * d)); }, 0, R.r_max());
    const double expected = std::cos(kPi / 4) / kPi * (floor_part + wall_part) * m.R_d.r / R.R_d();
    Image row(24, 1);
    for (int x = 0; x < 24; ++x) row.set(x, 0, img.at(x, y));
    const Stats st = pixel_stats(row);
    // 4 standard errors, plus 2 %: the expectation is taken at the row centre, the row spans
    // 0.44 mm of d. Near the crease L rises about 11 % above the flat value (the wall adds).
    EXPECT_NEAR(st.mean.r, expected, 4 * st.stderr_.r + 0.02 * expected)
        << "row " << y << " d = " << d << " mm, stderr " << st.stderr_.r << ", flat value "
        << std::cos(kPi / 4) / kPi * m.R_d.r;
  }
}

}  // namespace
}  // namespace skin::render
