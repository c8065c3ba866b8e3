// Colour and texture fits: sRGB round trip within 1 CIEDE2000 against `skin color`'s own path
// (skin_spectrum), the table interpolation against the exact model, parsing, and the EXR maps.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <filesystem>
#include <random>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "skin/fit/color_fit.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/util/error.hpp"

#include "test_params.hpp"
#include "test_support.hpp"

using namespace skin::fit;
namespace color = skin::color;

namespace {
using skin_test::params;
}  // namespace

// In-gamut colours: rendered by the model itself from parameters over the paper's ranges, then
// rounded to 8-bit sRGB as a user would give them. The fitted parameters' colour, computed the
// way `skin color` does (skin_spectrum with the same solver), must be within 1 dE2000 of the
// 8-bit input. Multipole over a 5 x 3 x 3 grid; adding-doubling (`skin color`'s default) on a
// smaller one (each of its evaluations costs ~70 multipole ones).
namespace {
void srgb_round_trip(const char* solver_name, const std::vector<double>& cms,
                     const std::vector<double>& bms, const std::vector<double>& chs) {
  ColorFitOptions o = skin_test::multipole_color_options();
  o.model = forward_model(solver_name);
  const skin::transport::Model& solver = skin::transport::find_model(solver_name);
  const ColorFitter fitter(o);
  const color::Colorimetry cm{skin::physics::WavelengthGrid{}};
  for (double c_m : cms)
    for (double b_m : bms)
      for (double c_h : chs) {
        const auto truth = skin::model::skin_spectrum(params(c_m, b_m, c_h), {}, solver);
        const auto s8 = truth.color.srgb8;
        const color::Rgb input{color::srgb_decode(s8[0] / 255.0), color::srgb_decode(s8[1] / 255.0),
                               color::srgb_decode(s8[2] / 255.0)};
        const ColorFitResult r = fitter.fit(input);
        const auto fitted = skin::model::skin_spectrum(r.parameters, {}, solver);
        const double de = color::delta_e_2000(color::summarize_rgb(cm, input).lab, fitted.color.lab);
        SCOPED_TRACE(::testing::Message() << solver_name << " " << truth.parameters << " -> " << r);
        EXPECT_LT(de, 1.0);
        // The fitter reaches Lab through white-balanced linear sRGB, skin color through XYZ: the
        // two paths agree to the rounding of the 4-digit IEC matrices (~1e-5 dE).
        EXPECT_NEAR(de, r.delta_e, 1e-3);
      }
}
}  // namespace

TEST(ColorFit, SrgbRoundTripWithinOneDeltaEMultipole) {
  srgb_round_trip("multipole", {0.002, 0.01, 0.05, 0.2, 0.45}, {0.0, 0.5, 1.0},
                  {0.002, 0.02, 0.12});
}

TEST(ColorFit, SrgbRoundTripWithinOneDeltaEAccurate) {
  // (Three of the twelve under the sanitizers, where each fit takes ~10 CPU-s.)
  srgb_round_trip("accurate", {0.005, 0.05, 0.3}, skin::test::sanitized({0.3, 0.8}),
                  skin::test::sanitized({0.005, 0.05}));
}

// With beta_m free but regularised, flat directions go to the prior: a fit of the colour of a
// beta_m = 0.7 skin returns close to 0.7; fixing beta_m (not free) keeps it exactly.
TEST(ColorFit, MelaninBlendResolvedByPriorOrFixed) {
  const auto truth = skin::model::skin_spectrum(params(0.01, 0.7, 0.01), {}, skin::transport::find_model("multipole"));
  ColorFitOptions o = skin_test::multipole_color_options();
  o.free = {Parameter::melanin, Parameter::hemoglobin};
  o.start.melanin_blend = 0.3;
  const ColorFitResult fixed = ColorFitter(o).fit(truth.color.srgb_linear);
  EXPECT_DOUBLE_EQ(fixed.parameters.melanin_blend, 0.3);
  const ColorFitResult reg = ColorFitter(skin_test::multipole_color_options()).fit(truth.color.srgb_linear);
  EXPECT_NEAR(reg.parameters.melanin_blend, 0.7, 0.1);
  EXPECT_LT(reg.delta_e, 0.2);
}

TEST(ColorFit, Parsing) {
  const color::Rgb a = parse_srgb8("216,168,144"), b = parse_hex("#d8a890"), c = parse_hex("D8A890");
  EXPECT_DOUBLE_EQ(a.r, b.r);
  EXPECT_DOUBLE_EQ(a.b, c.b);
  EXPECT_NEAR(a.r, color::srgb_decode(216 / 255.0), 1e-15);
  EXPECT_THROW(parse_srgb8("1,2"), skin::util::InputError);
  EXPECT_THROW(parse_srgb8("1,2,300"), skin::util::InputError);
  EXPECT_THROW(parse_srgb8("a,2,3"), skin::util::InputError);
  EXPECT_THROW(parse_hex("d8a89"), skin::util::InputError);
  EXPECT_THROW(parse_hex("g8a890"), skin::util::InputError);
  ColorFitOptions o = skin_test::multipole_color_options();
  o.free = {Parameter::oxygenation};
  EXPECT_THROW(ColorFitter{o}, skin::util::InputError);
}

// The texture path interpolates a table (40 x 6 x 40 nodes, log-spaced in C_m and C_h; R_d at
// 10 nm interpolated to the 2 nm colour grid). Its colour must stay within 0.3 dE2000 of the
// exact model anywhere in the box (random points, fixed seed), so that the error map measures
// the fit, not the table.
TEST(TextureFit, TableInterpolationMatchesExactModel) {
  const TextureFitter tex(skin_test::multipole_color_options());
  const ColorFitter exact(skin_test::multipole_color_options());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  for (int i = 0; i < 60; ++i) {
    const auto p = params(0.001 * std::pow(500.0, u(rng)), u(rng), 0.001 * std::pow(200.0, u(rng)));
    worst = std::max(worst, color::delta_e_2000(tex.lab(p), exact.lab(p)));
  }
  EXPECT_LT(worst, 0.3);
}

// A texel's uncertainty (TextureFitter::fit_color, the maps' uncertainty.<key> channels) comes
// from the table's derivatives; the colour fit's from its LM Jacobian on the model itself. For
// colours of the paper model inside its bounds both describe the same covariance: within 15 %
// (10.4 % at worst when written, beta_m's: the trilinear table's slope is a cell's secant, and
// beta_m has 6 nodes over 0-1).
TEST(TextureFit, TexelUncertaintyIsTheColourFits) {
  const TextureFitter tex(skin_test::multipole_color_options());
  const ColorFitter exact(skin_test::multipole_color_options());
  double worst = 0;
  for (const auto& p : {params(0.02, 0.5, 0.01), params(0.08, 0.8, 0.03), params(0.005, 0.6, 0.004)}) {
    const color::Rgb rgb = skin::model::skin_spectrum(p, {}, skin::transport::find_model("multipole")).color.srgb_linear;
    const ColorFitResult a = tex.fit_color(rgb), b = exact.fit(rgb);
    ASSERT_EQ(a.free, b.free);
    ASSERT_EQ(a.uncertainty.size(), b.uncertainty.size());
    for (std::size_t k = 0; k < a.uncertainty.size(); ++k) {
      worst = std::max(worst, std::abs(a.uncertainty[k] / b.uncertainty[k] - 1));
    }
  }
  std::printf("texel uncertainty within %.1f %% of the colour fit's\n", 100 * worst);
  EXPECT_LT(worst, 0.15);
}

// An albedo texture holding NaN or a value outside [0, 1] (an EXR can) is refused before any
// table is built, naming the texel: before, NaN reached std::lround (undefined) and 1.7 was
// clamped to 1 without a word.
TEST(TextureFit, TexelsOutsideAnAlbedoAreRefusedByName) {
  const TextureFitter tex(skin_test::multipole_color_options());
  for (const float bad : {std::nanf(""), 1.7f, -0.1f, std::numeric_limits<float>::infinity()}) {
    Image img(3, 2);
    img.rgb.assign(img.rgb.size(), 0.5f);
    img.rgb[(1 * 3 + 2) * 3 + 1] = bad;  // texel (2, 1), channel G
    try {
      tex.fit(img);
      ADD_FAILURE() << bad << " accepted";
    } catch (const skin::util::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("texture: texel (2, 1) channel G = "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("allowed: a linear albedo within [0, 1]"), std::string::npos) << e.what();
    }
  }
}

TEST(TextureFit, EveryTexelGetsTheFitOfItsOwnColour) {
  // The texture path solves each distinct colour once and hands its result to every texel of
  // that colour (a hash of the colours, which grows past its first 4096 slots here). 80 x 80
  // texels of 3000 colours in random order, each colour repeated 2-3 times: every texel's maps
  // equal the single-colour fit of its own colour, bit for bit, and the bound counts add up
  // texel by texel.
  const int w = 80, h = 80;
  std::mt19937 rng(20261204);
  std::uniform_int_distribution<int> channel(0, 65535);
  std::vector<std::array<int, 3>> colours(3000);
  for (auto& c : colours) c = {channel(rng), channel(rng), channel(rng)};
  Image img(w, h);
  std::vector<std::size_t> which(static_cast<std::size_t>(w * h));
  std::uniform_int_distribution<std::size_t> pick(0, colours.size() - 1);
  for (std::size_t i = 0; i < which.size(); ++i) {
    which[i] = i < colours.size() ? i : pick(rng);
    for (int c = 0; c < 3; ++c)
      img.rgb[i * 3 + static_cast<std::size_t>(c)] = static_cast<float>(colours[which[i]][static_cast<std::size_t>(c)] / 65535.0);
  }
  std::shuffle(which.begin(), which.end(), rng);  // (texel order no longer follows the colours' order)
  for (std::size_t i = 0; i < which.size(); ++i)
    for (int c = 0; c < 3; ++c)
      img.rgb[i * 3 + static_cast<std::size_t>(c)] = static_cast<float>(colours[which[i]][static_cast<std::size_t>(c)] / 65535.0);
  const TextureFitter fitter(skin_test::multipole_color_options());
  const ParameterMaps maps = fitter.fit(img);
  std::vector<ColorFitResult> single(colours.size());
  for (std::size_t q = 0; q < colours.size(); ++q) {
    const auto& c = colours[q];
    // The texture path reads each channel as a 16-bit value k and fits k / 65535.
    single[q] = fitter.fit_color({c[0] / 65535.0, c[1] / 65535.0, c[2] / 65535.0});
  }
  std::array<std::size_t, 3> at_bound{};
  std::size_t any_bound = 0;
  for (std::size_t i = 0; i < which.size(); ++i) {
    const ColorFitResult& r = single[which[i]];
    ASSERT_EQ(maps.melanin[i], static_cast<float>(r.parameters.melanin)) << i;
    ASSERT_EQ(maps.melanin_blend[i], static_cast<float>(r.parameters.melanin_blend)) << i;
    ASSERT_EQ(maps.hemoglobin[i], static_cast<float>(r.parameters.hemoglobin)) << i;
    ASSERT_EQ(maps.error[i], static_cast<float>(r.delta_e)) << i;
    ASSERT_EQ(r.at_bound.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) at_bound[k] += r.at_bound[k] ? 1 : 0;
    any_bound += (r.at_bound[0] || r.at_bound[1] || r.at_bound[2]) ? 1 : 0;
  }
  EXPECT_EQ(maps.at_bound, at_bound);
  EXPECT_EQ(maps.any_at_bound, any_bound);
  // Random colours are mostly far outside skin's gamut: many fits end on a bound.
  EXPECT_GT(any_bound, 100u);
}

TEST(TextureFit, PngToExrMapsRoundTrip) {
  // 12 x 5 texture: each column a model colour (C_m varies), rows vary C_h; one pixel pure blue
  // (far outside the skin gamut: large error expected there).
  const int w = 12, h = 5;
  std::vector<unsigned char> px(static_cast<std::size_t>(w * h * 3));
  std::vector<skin::physics::SkinParameters> truth;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto p = params(0.002 * std::pow(1.6, x), 0.7, 0.002 * std::pow(2.5, y));
      truth.push_back(p);
      const auto s8 = skin::model::skin_spectrum(p, {}, skin::transport::find_model("multipole")).color.srgb8;
      for (int c = 0; c < 3; ++c) px[static_cast<std::size_t>((y * w + x) * 3 + c)] = static_cast<unsigned char>(s8[static_cast<std::size_t>(c)]);
    }
  px[0] = 0, px[1] = 0, px[2] = 255;
  const auto dir = std::filesystem::temp_directory_path();
  const std::string png = (dir / "skin_fit_test_albedo.png").string();
  const std::string exr = (dir / "skin_fit_test_maps.exr").string();
  ASSERT_NE(stbi_write_png(png.c_str(), w, h, 3, px.data(), w * 3), 0);
  const Image img = skin::image::read_image(png);
  ASSERT_EQ(img.width, w);
  ASSERT_EQ(img.height, h);
  const ParameterMaps maps = TextureFitter(skin_test::multipole_color_options()).fit(img);
  for (std::size_t i = 1; i < truth.size(); ++i) EXPECT_LT(maps.error[i], 1.0) << i;
  EXPECT_GT(maps.error[0], 10.0);  // pure blue is no skin colour
  // Light skin: C_m is well determined by colour (within 15 %).
  EXPECT_NEAR(maps.melanin[1], truth[1].melanin, 0.15 * truth[1].melanin);
  write_parameter_maps(maps, exr);
  const ParameterMaps back = read_parameter_maps(exr);
  ASSERT_EQ(back.width, w);
  ASSERT_EQ(back.height, h);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_EQ(back.melanin[i], maps.melanin[i]);
    EXPECT_EQ(back.melanin_blend[i], maps.melanin_blend[i]);
    EXPECT_EQ(back.hemoglobin[i], maps.hemoglobin[i]);
    EXPECT_EQ(back.error[i], maps.error[i]);
  }
  EXPECT_THROW(skin::image::read_image((dir / "no_such_texture.png").string()), skin::util::InputError);
}
