// The `skin` command as a user runs it: golden output, formats, and every bad-input case
// (one clear line naming the parameter, exit code 2, no output file, existing files untouched).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "cli_fixture.hpp"
#include "skin_test_paths.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;
using skin_test::Cli;
using skin_test::CmdResult;
using skin_test::slurp;

namespace {

void expect_close(const json& a, const json& b, const std::string& path) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    // Golden values were written by this program; 1e-9 relative allows for a different compiler
    // or libm, not for a change of the physics.
    EXPECT_NEAR(x, y, 1e-9 * std::max(std::abs(y), 1e-12)) << path;
  } else if (a.is_array() && b.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << path;
    for (std::size_t i = 0; i < a.size(); ++i) expect_close(a[i], b[i], path + "[" + std::to_string(i) + "]");
  } else if (a.is_object() && b.is_object()) {
    for (auto it = b.begin(); it != b.end(); ++it) {
      ASSERT_TRUE(a.contains(it.key())) << path << "." << it.key();
      expect_close(a[it.key()], it.value(), path + "." + it.key());
    }
  } else {
    EXPECT_EQ(a, b) << path;
  }
}

}  // namespace

TEST_F(Cli, SpectrumJsonMatchesGolden) {
  const CmdResult r = run("spectrum --preset caucasian --lambda-step 10 --solver multipole --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json got = json::parse(r.out);
  const json golden = json::parse(slurp(fs::path(SKIN_SOURCE_DIR) / "tests/cli/golden/spectrum_caucasian.json"));
  expect_close(got, golden, "spectrum");
  // The contract other work builds on.
  for (const char* k : {"wavelength_nm", "R_d"}) EXPECT_EQ(got[k].size(), 31u) << k;
  for (const char* layer : {"epidermis", "dermis"})
    for (const char* k : {"sigma_a", "sigma_s_prime"}) EXPECT_EQ(got[layer][k].size(), 31u);
  EXPECT_EQ(got["color"]["srgb8"].size(), 3u);
  EXPECT_EQ(got["color"]["hex"].get<std::string>().size(), 7u);
}

TEST_F(Cli, ColorEqualsSpectrumColor) {
  const CmdResult a = run("color --preset asian --format json");
  const CmdResult b = run("spectrum --preset asian --format json");
  ASSERT_EQ(a.code, 0);
  ASSERT_EQ(b.code, 0);
  EXPECT_EQ(json::parse(a.out)["color"], json::parse(b.out)["color"]);
}

TEST_F(Cli, OverridesApplyOnTopOfPreset) {
  const json j = json::parse(run("spectrum --preset african --melanin 0.2 --format json").out);
  EXPECT_EQ(j["parameters"]["melanin"], 0.2);
  EXPECT_EQ(j["parameters"]["hemoglobin"], 0.05);  // from the preset
}

TEST_F(Cli, LayersOneSemiInfiniteLayerIsTheClassicDipole) {
  const CmdResult r = run("layers --solver multipole --layer sigma_a=0.01,sigma_s_prime=1 --radius 0.5 --radius 1 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(r.out);
  // alpha' = 1 / 1.01, A(1.4) = 3.2504: R_d = 0.6141 (closed form of Jensen et al. 2001).
  EXPECT_NEAR(j["R_d"].get<double>(), 0.61409, 1e-4);
  EXPECT_EQ(j["T_d"].get<double>(), 0.0);
  EXPECT_EQ(j["profile"]["r_mm"].size(), 2u);
  EXPECT_EQ(j["profile"]["R"].size(), 2u);
}

TEST_F(Cli, AccurateSpectrumMatchesGoldenAndIsTheDefault) {
  const CmdResult r = run("spectrum --preset african --lambda-step 10 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json got = json::parse(r.out);
  EXPECT_EQ(got["solver"], "accurate");
  expect_close(got, json::parse(slurp(fs::path(SKIN_SOURCE_DIR) / "tests/cli/golden/spectrum_african_accurate.json")),
               "spectrum");
  // Dark skin in the blue: the multipole overstates R_d (docs/accurate-solver.md, sec. 1).
  const json mp = json::parse(run("spectrum --preset african --lambda-step 10 --solver multipole --format json").out);
  EXPECT_GT(mp["R_d"][5].get<double>(), 1.5 * got["R_d"][5].get<double>());  // 450 nm
}

// Off its skin table the accurate profile is solved by radiative transfer in the
// spatial-frequency domain: no warning, and the JSON says the profile is inside the range. A
// dark top layer (alpha' = 0.038) over a bright half-space.
TEST_F(Cli, LayersOutsideTheTablesDoNotWarn) {
  const CmdResult r = run("layers --layer sigma_a=50,sigma_s_prime=2,thickness=0.05 "
                          "--layer sigma_a=0.001,sigma_s_prime=10 --radius 0.3 --radius 3 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const json j = json::parse(r.out);
  EXPECT_EQ(j["validity"], json::parse(R"({"totals": true, "profile": true})"));
  EXPECT_GT(j["profile"]["R"][0].get<double>(), j["profile"]["R"][1].get<double>());
  EXPECT_GT(j["profile"]["R"][1].get<double>(), 0.0);
}

// Adaptive sampling without --spp stops at its target: no time estimate from its 65536-spp bound
// (which warned of hours for a render of seconds); with --spp the bound is the user's and is
// estimated as any request.
TEST_F(Cli, AdaptiveRenderWithoutSppIsNotEstimatedFromItsBound) {
  const CmdResult r = run("render --resolution 256x256 --max-depth 1 --target-error 0.9 --threads 1 -o adaptive.png");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("would take about"), std::string::npos) << r.err;
  const CmdResult big = run("render --resolution 16384x16384 --target-error 0.5 --spp 100000 --threads 1 -o big.png");
  EXPECT_EQ(big.code, 2);
  EXPECT_NE(big.err.find("would take about"), std::string::npos) << big.err;
}

// The multipole's own bad regime (a layer thinner than z_r) through the same check.
TEST_F(Cli, LayersWarnWhereTheMultipoleLayerIsThinnerThanZr) {
  const CmdResult r = run("layers --solver multipole --layer sigma_a=0.5,sigma_s_prime=4.5,thickness=0.1 "
                          "--layer sigma_a=0.05,sigma_s_prime=2.5 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("skin: warning: solver multipole: totals and profile outside its validated range: "
                       "layer 1 is thinner than z_r"), std::string::npos) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["validity"]["totals"], false);
  EXPECT_EQ(j["validity"]["profile"], false);
  // The same for skin: an epidermis of 0.1 mm is thinner than z_r in the red.
  const CmdResult s = run("spectrum --solver multipole --epidermis-thickness 0.1 --lambda-step 100 --format json");
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.err.find("skin: warning: solver multipole: totals and profile outside its validated range: "
                       "at 500 nm .. 700 nm (3 of 4): layer 1 is thinner than z_r"), std::string::npos) << s.err;
  EXPECT_EQ(run("spectrum --epidermis-thickness 0.1 --lambda-step 100 --format json").err, "");
}

// Skin with another anisotropy: no warning either (g 0.6 is outside the skin table's offsets:
// solved).
TEST_F(Cli, ProfileOfAnotherGDoesNotWarn) {
  // One wavelength (each is solved: ~12 s under the sanitizers).
  const CmdResult r = run("profile --g 0.6 --lambda-min 700 --lambda-max 700 --samples 4 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(json::parse(r.out)["validity"]["profile"], true);
}

TEST_F(Cli, LayersSlabHasTransmittance) {
  const CmdResult r = run("layers --layer sigma_a=0.1,sigma_s_prime=5,thickness=1 "
                    "--layer sigma_a=0.5,sigma_s_prime=2,thickness=2,eta=1.33 --eta-below 1.5 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_GT(j["T_d"].get<double>(), 0.0);
  EXPECT_LT(j["R_d"].get<double>() + j["T_d"].get<double>(), 1.0);
}

TEST_F(Cli, ProfileFormats) {
  const CmdResult csv = run("profile --rgb --samples 8 --format csv");
  ASSERT_EQ(csv.code, 0) << csv.err;
  EXPECT_EQ(csv.out.substr(0, csv.out.find('\n')), "r_mm,R.r [1/mm^2],R.g [1/mm^2],R.b [1/mm^2],R_d.r,R_d.g,R_d.b");
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 9);
  const json j = json::parse(run("profile --samples 4 --lambda-step 100 --format json").out);
  EXPECT_EQ(j["R"].size(), 4u);      // 400, 500, 600, 700 nm
  EXPECT_EQ(j["R"][0].size(), 4u);   // radii
}

TEST_F(Cli, OutputFileAndPlots) {
  ASSERT_EQ(run("spectrum --format csv -o s.csv --plot s.png").code, 0);
  EXPECT_TRUE(fs::exists(dir_ / "s.csv"));
  EXPECT_EQ(slurp(dir_ / "s.png").substr(1, 3), "PNG");
  ASSERT_EQ(run("profile --rgb --plot p.svg -o p.json --format json").code, 0);
  EXPECT_NE(slurp(dir_ / "p.svg").find("<svg"), std::string::npos);
  // No temporary files are left behind.
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

struct BadInput {
  const char* args;
  const char* message;  // must appear in the one-line error
};

std::ostream& operator<<(std::ostream& os, const BadInput& b) {
  return os << "skin " << b.args << " -> \"" << b.message << '"';
}

class CliBadInput : public Cli, public ::testing::WithParamInterface<BadInput> {};

TEST_P(CliBadInput, OneLineExitCode2NoFileAndExistingFileKept) {
  {
    std::ofstream keep(dir_ / "out.json");
    keep << "precious";
  }
  const CmdResult r = run(std::string(GetParam().args) + " -o out.json");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(GetParam().message), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("skin: error: "), 0u) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(slurp(dir_ / "out.json"), "precious");
  EXPECT_EQ(file_count(), 1u);  // nothing else written
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliBadInput,
    ::testing::Values(
        BadInput{"spectrum --melanin 1.5", "melanin (C_m) = 1.5 is out of range: allowed range is [0, 1]"},
        BadInput{"spectrum --melanin-blend -0.1", "melanin-blend (beta_m) = -0.1 is out of range"},
        BadInput{"color --hemoglobin nan", "hemoglobin (C_h) = nan is out of range"},
        BadInput{"profile --hemoglobin inf", "hemoglobin (C_h) = inf is out of range"},
        BadInput{"spectrum --epidermis-thickness 0", "epidermis-thickness = 0 mm is out of range: must be a finite number > 0"},
        BadInput{"spectrum --preset martian", "preset = 'martian' is unknown: known presets are caucasian"},
        BadInput{"spectrum --lambda-step 7", "lambda_step = 7 nm is out of range"},
        BadInput{"spectrum --melanin abc", "--melanin"},
        BadInput{"layers --layer sigma_a=0.1", "sigma_a and sigma_s_prime are required"},
        BadInput{"layers --layer 'sigma_a=0.1;sigma_s_prime=2'", "is malformed"},
        BadInput{"layers --layer sigma_a=x,sigma_s_prime=2", "value of sigma_a ('x') is not a number"},
        BadInput{"layers --layer sigma_a=0.1,sigma_s_prime=2,colour=3", "unknown key 'colour'"},
        BadInput{"layers --layer sigma_a=0.1,sigma_s_prime=2 --layer sigma_a=0.1,sigma_s_prime=2,thickness=1",
                 "layer 1 thickness = inf is out of range: only the last layer may be semi-infinite"},
        BadInput{"layers --layer sigma_a=0.1,sigma_s_prime=2,thickness=-1", "layer 1 thickness = -1 mm is out of range"},
        BadInput{"layers --layer sigma_a=-1,sigma_s_prime=2", "layer 1 sigma_a = -1 1/mm is out of range"},
        BadInput{"layers --layer sigma_a=0.1,sigma_s_prime=0", "layer 1 sigma_s_prime = 0 1/mm is out of range"},
        BadInput{"layers --layer sigma_a=0.1,sigma_s_prime=1,eta=nan", "layer 1 eta = nan is out of range"},
        BadInput{"spectrum --plot plot.gif", "unsupported extension"},
        BadInput{"color --solver monte-carlo", "--solver"}));

TEST_F(Cli, MissingDirectoryForOutput) {
  const CmdResult r = run("spectrum --format json -o no/such/dir/out.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

TEST_F(Cli, HelpStatesUnitsAndRanges) {
  const CmdResult r = run("spectrum --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("[0, 1]"), std::string::npos);
  EXPECT_NE(r.out.find("[nm]"), std::string::npos);
  const CmdResult l = run("layers --help");
  EXPECT_NE(l.out.find("1/mm"), std::string::npos);
}
