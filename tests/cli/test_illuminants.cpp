// skin color --illuminant and skin illuminants as a user runs them: D65 stays the default and
// unchanged, other illuminants change the colour, bad names are one line, the swatch figure.
#include <nlohmann/json.hpp>

#include "cli_fixture.hpp"

using namespace skin_test;
using json = nlohmann::json;

TEST_F(Cli, ColorUnderD65IsTheDefaultAndUnchanged) {
  const CmdResult plain = run("color --preset tanned --format json");
  const CmdResult d65 = run("color --preset tanned --illuminant d65 --format json");
  ASSERT_EQ(plain.code, 0) << plain.err;
  ASSERT_EQ(d65.code, 0) << d65.err;
  EXPECT_EQ(plain.out, d65.out);
  const json j = json::parse(plain.out);
  EXPECT_EQ(j["illuminant"], "D65");
  EXPECT_EQ(j["color"]["hex"], "#a98f74");  // README, `skin fit --hex a98f74`
  // The table names the illuminant only in the XYZ line (as before).
  const CmdResult table = run("color --preset tanned --format table");
  EXPECT_EQ(table.out.rfind("XYZ (D65, Y_white = 1)  ", 0), 0u) << table.out;
  EXPECT_EQ(table.out.find("Bradford"), std::string::npos);
}

TEST_F(Cli, ColorUnderAnotherIlluminant) {
  const CmdResult a = run("color --preset tanned --illuminant A --format json");
  ASSERT_EQ(a.code, 0) << a.err;
  const json j = json::parse(a.out);
  EXPECT_EQ(j["illuminant"], "A");
  const json d65 = json::parse(run("color --preset tanned --format json").out);
  // Far less blue under A in XYZ; after the Bradford adaptation the colour is close to D65's.
  EXPECT_LT(j["color"]["XYZ"][2].get<double>(), 0.5 * d65["color"]["XYZ"][2].get<double>());
  EXPECT_NE(j["color"]["hex"], d65["color"]["hex"]);
  const CmdResult table = run("color --preset tanned --illuminant LED-B3 --format table");
  EXPECT_EQ(table.out.rfind("XYZ (LED-B3, Y_white = 1)  ", 0), 0u) << table.out;
  EXPECT_NE(table.out.find("Bradford adaptation LED-B3 -> D65"), std::string::npos);
}

TEST_F(Cli, UnknownIlluminantIsOneLineListingTheAllowed) {
  for (const char* args : {"color --illuminant F3", "illuminants --compare --illuminant D60"}) {
    const CmdResult r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("--illuminant: illuminant = '"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("is unknown: must be one of D65, D50, A, FL2, FL7, FL11, LED-B1, LED-B2, "
                         "LED-B3, LED-B4, LED-B5, LED-BH1, LED-RGB1, LED-V1, LED-V2"),
              std::string::npos)
        << r.err;
  }
  // Options of the comparison without --compare are refused, nothing written.
  const CmdResult r = run("illuminants --swatches s.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--swatches is given without --compare"), std::string::npos) << r.err;
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, IlluminantsListWhitePoints) {
  const CmdResult r = run("illuminants --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j.size(), 15u);
  EXPECT_EQ(j[0]["name"], "D65");
  EXPECT_NEAR(j[0]["x"].get<double>(), 0.31272, 1e-4);
  EXPECT_EQ(j[0]["light_srgb_linear"], json::array({1.0, 1.0, 1.0}));
  EXPECT_EQ(j[2]["name"], "A");
  EXPECT_NEAR(j[2]["x"].get<double>(), 0.44758, 1e-4);
  EXPECT_NEAR(j[2]["y"].get<double>(), 0.40745, 1e-4);
}

TEST_F(Cli, CompareAndSwatches) {
  const CmdResult r = run("illuminants --compare --illuminant D65 --illuminant A --solver multipole "
                          "--format json --swatches s.png");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["colors"].size(), 2u * 16u);  // presets (the paper's 6, monk-01 ... monk-10) x illuminants
  for (const json& c : j["colors"]) {
    const double dE = c["delta_e_2000"].get<double>();
    if (c["illuminant"] == "D65") EXPECT_LT(dE, 1e-3) << c["preset"];  // the same by construction
    else EXPECT_GT(dE, 0.3) << c["preset"];  // per-channel products miss the spectral interplay
  }
  const std::string png = slurp(dir_ / "s.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}
