// The validation report: cases are valid, extra solver columns appear everywhere, plots are
// written, and the numbers in the report are the ones computed.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <sstream>

#include "skin/mc/validation.hpp"
#include "skin/transport/stack.hpp"

namespace {

namespace mc = skin::mc;

TEST(ValidationCases, PresetsAndGenericStacksAreValidAndUnique) {
  const auto presets = mc::preset_cases({450, 550, 650});
  EXPECT_EQ(presets.size(), 18u);  // six presets of the paper, three wavelengths
  auto generic = mc::generic_cases();
  EXPECT_GE(generic.size(), 10u);
  std::set<std::string> ids;
  int regime = 0;
  for (const auto& c : presets) ids.insert(c.id);
  for (const auto& c : generic) {
    ids.insert(c.id);
    EXPECT_NO_THROW(c.stack.validate()) << c;
    regime += c.diffusion_regime;
  }
  EXPECT_EQ(ids.size(), presets.size() + generic.size());
  EXPECT_GE(regime, 3);
}

TEST(ValidationReport, ExtraSolverColumnAppearsInTablesAndPlots) {
  // Two cheap cases, few photons; a second "solver" that is the multipole scaled by 1.1, so that
  // its error is known: (1.1 R_diff - R_mc) / R_mc.
  auto cases = mc::generic_cases();
  std::vector<mc::ValidationCase> two{cases[3], cases[4]};  // absorbing semi-infinite: fast
  mc::SolverColumn scaled = mc::solver_column(skin::transport::find_model("multipole"));
  scaled.name = "scaled-by-1.1";
  scaled.R_d = [](const skin::LayerStack& s) { return 1.1 * skin::DiffusionStack(s).R_d(); };
  scaled.profile = {};  // no profile: the report must cope
  mc::Options o;
  o.photons = 3000;
  o.bins = 40;
  int lines = 0;
  const auto run = mc::run_validation(two, {mc::solver_column(skin::transport::find_model("multipole")), scaled}, o,
                                      [&](const std::string&) { ++lines; });
  EXPECT_EQ(lines, 2);
  ASSERT_EQ(run.cases.size(), 2u);
  for (const auto& c : run.cases) {
    EXPECT_NEAR(c.R_d[1], 1.1 * c.R_d[0], 1e-12);
    EXPECT_NEAR(c.relative_error(1), (1.1 * c.R_d[0] - c.mc.R_d) / c.mc.R_d, 1e-12);
    EXPECT_EQ(c.R[0].size(), c.mc.r_mm.size());
    EXPECT_TRUE(c.R[1].empty());
  }
  const auto dir = std::filesystem::temp_directory_path() / "skin_mc_validation_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ostringstream md;
  mc::write_validation_report(md, run, dir.string(), "plots/");
  const std::string text = md.str();
  EXPECT_NE(text.find("| multipole R_d | error | scaled-by-1.1 R_d | error |"), std::string::npos)
      << text;
  EXPECT_NE(text.find("**scaled-by-1.1**"), std::string::npos);
  EXPECT_NE(text.find("(plots/profile_" + two[0].id + ".png)"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / ("profile_" + two[0].id + ".png")));
  EXPECT_TRUE(std::filesystem::exists(dir / "rd_relative_error.png"));
  std::filesystem::remove_all(dir);
}

}  // namespace

// The report's plots draw text through Cairo, whose fontconfig keeps a small cache alive until
// exit; LeakSanitizer reports it as a leak in sanitizer builds. It is not ours: suppress only it.
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig\n"; }
