// One vocabulary: the parameter table drives every surface. `skin parameters` lists every
// parameter; each key works as a flag (dashes), each paper symbol as an alias, and each flag
// changes what it should (the colour, or the surface's specular lobe) and nothing else; --params
// reads the JSON the CLI writes, flags after it override it; bad files get one line and exit 2.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "cli_fixture.hpp"

namespace {
using json = nlohmann::json;
using skin_test::Cli;
using skin_test::CmdResult;

json parse(const CmdResult& r) {
  EXPECT_EQ(r.code, 0) << r.err;
  return json::parse(r.out);
}

TEST_F(Cli, ParametersListsEveryKeyAndEachWorksAsFlagAndSymbol) {
  const json table = parse(run("parameters --format json"));
  ASSERT_EQ(table.size(), 15u);  // every member of SkinParameters (tests/physics checks the count)
  const json defaults = parse(run("spectrum --format json --lambda-step 100"))["parameters"];
  for (const auto& row : table) {
    for (const char* k : {"key", "symbol", "unit", "min", "max", "default", "help"})
      ASSERT_TRUE(row.contains(k)) << row.dump();
    const std::string key = row["key"];
    ASSERT_TRUE(defaults.contains(key)) << key;
    // A value inside the range, away from the default.
    const double lo = row["min"].get<double>();
    const double hi = row["max"].is_null() ? lo + 2.0 : row["max"].get<double>();
    const double v = lo + 0.37 * (hi - lo) + (row["min_exclusive"].get<bool>() ? 1e-3 : 0.0);
    const std::string flag = row["flag"];
    const json got = parse(run("color --format json --lambda-step 100 " + flag + " " +
                               nlohmann::json(v).dump()))["parameters"];
    EXPECT_DOUBLE_EQ(got[key].get<double>(), v) << flag;
    if (!row["symbol"].is_null()) {
      const json alias = parse(run("color --format json --lambda-step 100 --" +
                                   row["symbol"].get<std::string>() + " " + json(v).dump()))["parameters"];
      EXPECT_DOUBLE_EQ(alias[key].get<double>(), v) << row["symbol"];
    }
  }
}

// Echoing a flag back is not enough: each parameter's flag changes the result it drives. Every
// parameter of the layers changes the colour (R_d through the transport); the surface's two
// (oiliness, roughness) leave it alone and change the exported specular lobe, eta its index.
// The export's values are read from the report of `skin export --target openpbr` (multipole: the
// specular terms do not depend on the solver, and it is fast off the skin table).
TEST_F(Cli, EachParameterFlagChangesWhatItShould) {
  const json table = parse(run("parameters --format json"));
  auto color = [&](const std::string& flags) {
    return parse(run("color --format json --lambda-step 100 " + flags))["color"]["XYZ"];
  };
  auto specular = [&](const std::string& flags) {
    const CmdResult r = run("export --target openpbr --solver multipole -o m.json " + flags);
    EXPECT_EQ(r.code, 0) << flags << ": " << r.err;
    const json values = json::parse(skin_test::slurp(dir_ / "m.fit.json"))["values"];
    return json{{"specular_weight", values["specular_weight"]},
                {"specular_roughness", values["specular_roughness"]},
                {"specular_ior", values["specular_ior"]}};
  };
  const json base_color = color(""), base_specular = specular("");
  // Which specular value each surface parameter drives; the others drive none.
  const std::map<std::string, std::string> surface = {
      {"oiliness", "specular_weight"}, {"roughness", "specular_roughness"}, {"eta", "specular_ior"}};
  for (const auto& row : table) {
    const std::string key = row["key"];
    const double lo = row["min"].get<double>();
    const double hi = row["max"].is_null() ? lo + 2.0 : row["max"].get<double>();
    const double v = lo + 0.37 * (hi - lo) + (row["min_exclusive"].get<bool>() ? 1e-3 : 0.0);
    const std::string flag = row["flag"].get<std::string>() + " " + json(v).dump();
    const bool of_the_surface = key == "oiliness" || key == "roughness";
    if (of_the_surface) {
      EXPECT_EQ(color(flag), base_color) << flag << " changes the colour";
    } else {
      EXPECT_NE(color(flag), base_color) << flag << " leaves the colour as it was";
    }
    if (!surface.count(key) && !(key == "melanin" || key == "g" || key == "bilirubin")) continue;
    // The surface's parameters, and three of the layers' as a check that those leave it alone.
    const json s = specular(flag);
    for (const auto& [name, value] : base_specular.items()) {
      const auto it = surface.find(key);
      if (it != surface.end() && it->second == name) {
        EXPECT_NE(s[name], value) << flag << " leaves " << name << " as it was";
      } else {
        EXPECT_EQ(s[name], value) << flag << " changes " << name;
      }
    }
  }
}

TEST_F(Cli, ParametersCsvAndTableHaveOneRowPerParameter) {
  const CmdResult csv = run("parameters --format csv");
  ASSERT_EQ(csv.code, 0);
  EXPECT_EQ(csv.out.find("key,flag,symbol,unit,min,max"), 0u);
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 16);
  const CmdResult table = run("parameters --format table");
  EXPECT_NE(table.out.find("melanin_blend            beta_m"), std::string::npos) << table.out;
}

TEST_F(Cli, ParamsFileRoundTripAndOverride) {
  // The parameters object `skin spectrum` writes gives back the same spectrum.
  const CmdResult s = run("spectrum --preset asian --melanin 0.2 --bilirubin 30 --format json "
                          "--lambda-step 50 -o spectrum.json");
  ASSERT_EQ(s.code, 0) << s.err;
  const json a = json::parse(skin_test::slurp(dir_ / "spectrum.json"));
  const json b = parse(run("spectrum --params spectrum.json --format json --lambda-step 50"));
  EXPECT_EQ(a["parameters"], b["parameters"]);
  EXPECT_EQ(a["R_d"], b["R_d"]);
  // A flag after --params overrides the file; one before it is overridden by the file.
  const json after = parse(run("color --params spectrum.json --melanin 0.05 --format json"));
  EXPECT_DOUBLE_EQ(after["parameters"]["melanin"].get<double>(), 0.05);
  const json before = parse(run("color --melanin 0.05 --params spectrum.json --format json"));
  EXPECT_DOUBLE_EQ(before["parameters"]["melanin"].get<double>(), 0.2);
  // A bare object with paper symbols, null for "not set", and a preset.
  std::ofstream(dir_ / "bare.json") << R"({"preset": "african", "C_m": 0.3, "beta_m": null})";
  const json bare = parse(run("color --params bare.json --format json"))["parameters"];
  EXPECT_DOUBLE_EQ(bare["melanin"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(bare["melanin_blend"].get<double>(), 0.7);
  EXPECT_DOUBLE_EQ(bare["hemoglobin"].get<double>(), 0.05);  // african's
}

struct BadParams {
  const char* content;
  const char* message;
};
class CliBadParams : public Cli, public ::testing::WithParamInterface<BadParams> {};
TEST_P(CliBadParams, OneLineExitTwo) {
  std::ofstream(dir_ / "p.json") << GetParam().content;
  const CmdResult r = run("spectrum --params p.json --format json");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(GetParam().message), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(r.out.empty());
}
INSTANTIATE_TEST_SUITE_P(
    Cases, CliBadParams,
    ::testing::Values(BadParams{R"({"melanin": true})", "melanin must be a number, not true"},
                      BadParams{R"({"melanin": "0.1"})", "melanin must be a number"},
                      BadParams{R"({"colour": 1})", "key 'colour' is unknown"},
                      BadParams{R"({"melanin": 2})", "melanin (C_m) = 2 is out of range"},
                      BadParams{R"({"melanin": 0.1)", "not valid JSON"},
                      BadParams{R"([1, 2])", "expected an object of parameter keys"},
                      BadParams{R"({"preset": "martian"})", "preset = 'martian' is unknown"}));

TEST_F(Cli, ParamsFileMissing) {
  const CmdResult r = run("color --params nothing.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("params = 'nothing.json': file not found"), std::string::npos) << r.err;
}

// skin layers answers in the order asked (repeats too); its layers say thickness_mm, as spectrum
// does; CSV carries the totals as columns and the units in the header.
TEST_F(Cli, LayersRadiiInTheOrderAskedAndOneKeyPerQuantity) {
  const std::string stack =
      "layers --layer sigma_a=0.5,sigma_s_prime=5,thickness=0.25 --layer sigma_a=0.05,sigma_s_prime=2.5 ";
  const json j = json::parse(run(stack + "--radius 3 --radius 0.1 --radius 1 --radius 0.1 --format json").out);
  EXPECT_EQ(j["profile"]["r_mm"], json::parse("[3, 0.1, 1, 0.1]"));
  const auto R = j["profile"]["R"];
  ASSERT_EQ(R.size(), 4u);
  EXPECT_GT(R[1].get<double>(), R[2].get<double>());  // 0.1 mm brighter than 1 mm
  EXPECT_GT(R[2].get<double>(), R[0].get<double>());  // 1 mm brighter than 3 mm
  EXPECT_EQ(R[1], R[3]);
  EXPECT_DOUBLE_EQ(j["layers"][0]["thickness_mm"].get<double>(), 0.25);
  EXPECT_TRUE(j["layers"][1]["thickness_mm"].is_null());
  const skin_test::CmdResult csv = run(stack + "--radius 1 --format csv");
  EXPECT_EQ(csv.out.substr(0, csv.out.find('\n')), "r_mm,R [1/mm^2],R_d,T_d,R_specular");
  EXPECT_EQ(csv.out.find('#'), std::string::npos);  // no comment lines
}
}  // namespace
