// The validation cases and runs (skin::mc) and their report (src/app): cases are valid, extra
// solver columns appear everywhere, plots are written, and the numbers in the report are the
// ones computed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <random>
#include <filesystem>
#include <set>
#include <sstream>

#include "../temp_dir.hpp"
#include "report_validation.hpp"
#include "skin/mc/validation.hpp"
#include "skin/transport/model.hpp"
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
  scaled.R_d = [](const skin::physics::LayerStack& s) { return 1.1 * skin::transport::DiffusionStack(s).R_d(); };
  scaled.profile = {};  // no profile: the report must cope
  mc::Options o;
  o.photons = 3000;
  o.bins = 40;
  std::vector<std::pair<std::size_t, std::size_t>> calls;
  std::vector<std::string> ids;
  const auto run = mc::run_validation(
      two, {mc::solver_column(skin::transport::find_model("multipole")), scaled}, o,
      [&](std::size_t done, std::size_t total, const mc::CaseResult& c) {
        calls.emplace_back(done, total);
        ids.push_back(c.c.id);
      });
  // Progress: once per case, in order, from the calling thread.
  EXPECT_EQ(calls, (std::vector<std::pair<std::size_t, std::size_t>>{{1, 2}, {2, 2}}));
  EXPECT_EQ(ids, (std::vector<std::string>{two[0].id, two[1].id}));
  ASSERT_EQ(run.cases.size(), 2u);
  for (const auto& c : run.cases) {
    EXPECT_NEAR(c.R_d[1], 1.1 * c.R_d[0], 1e-12);
    EXPECT_NEAR(c.relative_error(1), (1.1 * c.R_d[0] - c.mc.R_d) / c.mc.R_d, 1e-12);
    EXPECT_EQ(c.R[0].size(), c.mc.r_mm.size());
    EXPECT_TRUE(c.R[1].empty());
  }
  const skin::test::TempDir tmp("skin_validation_report");
  const std::filesystem::path& dir = tmp.path();
  std::ostringstream md;
  skin::cli::write_validation_report(md, run, dir.string(), "plots/");
  const std::string text = md.str();
  EXPECT_NE(text.find("| multipole R_d | error | scaled-by-1.1 R_d | error |"), std::string::npos)
      << text;
  EXPECT_NE(text.find("**scaled-by-1.1**"), std::string::npos);
  // The criterion of issue 15 per case, with the numbers of CaseResult::check_annuli.
  EXPECT_NE(text.find("| case | annuli | multipole: beyond | worst (at r) | scaled-by-1.1: beyond |"),
            std::string::npos) << text;
  for (const auto& c : run.cases) {
    const auto pc = c.check_annuli(0, 0.02, std::min(10.0, c.c.r_max), 0.05, 1e-6);
    char row[128];
    std::snprintf(row, sizeof row, "| %s | %d | %d | %+.1f %% (%.3g mm) | n/a | n/a |", c.c.id.c_str(),
                  pc.checked, pc.beyond, 100.0 * pc.worst, pc.worst_r);
    EXPECT_NE(text.find(row), std::string::npos) << row;
  }
  EXPECT_NE(text.find("(plots/profile_" + two[0].id + ".png)"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / ("profile_" + two[0].id + ".png")));
  EXPECT_TRUE(std::filesystem::exists(dir / "rd_relative_error.png"));
  // The numbers in the tables and the terminal line are the run's.
  for (const auto& c : run.cases) {
    char rd[64], err[32];
    std::snprintf(rd, sizeof rd, "%.5f +- %.5f", c.mc.R_d, c.mc.R_d_se);
    std::snprintf(err, sizeof err, "%+.2f %%", 100.0 * c.relative_error(1));
    EXPECT_NE(text.find(std::string("| ") + c.c.id + " | " + rd + " |"), std::string::npos) << rd;
    const std::string line = skin::cli::validation_case_line(c, run.solver_names);
    EXPECT_EQ(line.rfind(c.c.id + ": MC R_d " + rd + ", multipole ", 0), 0u) << line;
    EXPECT_NE(line.find(", scaled-by-1.1 "), std::string::npos) << line;
    EXPECT_NE(line.find(std::string("(") + err + ")"), std::string::npos) << line;
  }
}

TEST(ValidationCases, AnnulusCheckCountsWhatTheCriterionSays) {
  // A hand-made result: four annuli of 0.1 mm; the model off by 10 %, 30 %, 10 % and 12 %.
  mc::CaseResult c;
  c.c.r_max = 0.4;
  c.mc.r_mm = {0.05, 0.15, 0.25, 0.35};
  c.mc.R = {1.0, 0.1, 1e-3, 1e-7};
  c.mc.R_se = {0.001, 0.02, 1e-5, 1e-8};  // 0.1 %, 20 %, 1 %, 10 %
  c.R = {{1.1, 0.13, 1.1e-3, 1.12e-7}};
  // From 0: the first three annuli (the fourth is below 1e-6 of the peak); beyond 5 % + 3 SE: the
  // first (10 % > 5.3 %) and third (10 % > 8 %), not the second (30 % < 65 %).
  auto pc = c.check_annuli(0, 0.0, 10.0, 0.05, 1e-6);
  EXPECT_EQ(pc.checked, 3);
  EXPECT_EQ(pc.beyond, 2);
  EXPECT_NEAR(pc.worst, 0.3, 1e-12);
  // From 0.02 mm the first annulus (0-0.1 mm) is not inside; with floor 1e-8 the fourth counts
  // (12 % < 35 %).
  pc = c.check_annuli(0, 0.02, 10.0, 0.05, 1e-8);
  EXPECT_EQ(pc.checked, 3);
  EXPECT_EQ(pc.beyond, 1);
  EXPECT_NEAR(pc.worst_r, 0.15, 1e-12);
  // Up to 0.3 mm: the last annulus (0.3-0.4 mm) is not inside.
  EXPECT_EQ(c.check_annuli(0, 0.0, 0.3, 0.05, 1e-8).checked, 3);
}

TEST(ValidationCases, DomainCheckReportsTheWorstErrorOverItsAllowance) {
  // Three annuli of 0.1 mm centred at 0.1-0.3 mm: the first off by 4 % (allowed 5 % + 3 x 0.1 %),
  // the second with a 10 % standard error (not checked: above 3 %), the third off by 10 %
  // (allowed 5 % + 3 x 1 %).
  mc::CaseResult c;
  c.mc.r_mm = {0.1, 0.2, 0.3};
  c.mc.R = {1.0, 0.1, 1e-3};
  c.mc.R_se = {0.001, 0.01, 1e-5};
  c.R = {{1.04, 0.2, 0.9e-3}};
  c.mc.R_d = 0.5;
  c.mc.R_d_se = 0.001;
  c.R_d = {0.503};
  const auto pc = c.check_domain(0);
  EXPECT_EQ(pc.checked, 2);
  EXPECT_EQ(pc.beyond, 1);
  EXPECT_NEAR(pc.worst, -0.1, 1e-12);
  EXPECT_NEAR(pc.worst_share, 1e-4 / 8e-5, 1e-9);  // the third: beyond (> 1); the first 0.755
  EXPECT_NEAR(c.rd_share(0), 0.003 / 0.0055, 1e-9);
  EXPECT_TRUE(c.rd_within(0));
  c.R[0][2] = 1e-3;  // the third exact: the first is the worst, within its allowance
  EXPECT_NEAR(c.check_domain(0).worst_share, 0.04 / 0.053, 1e-9);
  EXPECT_EQ(c.check_domain(0).beyond, 0);
}

}  // namespace

// The report's plots draw text through Cairo, whose fontconfig keeps a small cache alive until
// exit; LeakSanitizer reports it as a leak in sanitizer builds. It is not ours: suppress only it.
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig\n"; }

namespace {

// Issue 31's check, on a fresh handful of cases drawn from the skin domain in every run (the
// seed is printed; SKIN_DOMAIN_SEED=N repeats a run): the default model within 5 % + 3 SE of the
// Monte Carlo in every annulus of 0.02-10 mm whose relative standard error is below 3 %, and R_d
// within 0.5 % + 3 SE. Up to 10^6 photons per case (~3-8 s each on 2 cores in Release; fewer
// photons where a photon takes many steps, below); Release only (scripts/test.sh). The
// multipole fails the same check in every case drawn so far (at least two of the four are
// required to fail, so that the check can fail).
std::uint64_t domain_seed() {
  if (const char* s = std::getenv("SKIN_DOMAIN_SEED")) return std::strtoull(s, nullptr, 10);
  return (static_cast<std::uint64_t>(std::random_device{}()) << 32) ^ std::random_device{}();
}

}  // namespace

TEST(SkinDomainAgainstMonteCarlo, FreshCasesWithinFivePercentAndThreeSE) {
  const std::uint64_t seed = domain_seed();
  RecordProperty("domain_seed", std::to_string(seed));
  std::cout << "skin domain seed " << seed << " (SKIN_DOMAIN_SEED=" << seed << " repeats it)\n";
  const auto cases = mc::domain_cases(4, seed);
  mc::Options o;
  o.bins = 500;  // annuli of 0.02 mm to 10 mm
  o.seed = 1;
  // 10^6 photons per case, fewer where a photon takes many steps, so that no draw costs minutes:
  // a nearly non-absorbing, strongly forward-scattering dermis (g 0.97, scattering x4 at 780 nm)
  // takes ~2000 steps per photon, 10^6 photons ~100 s on 2 cores (a CI run drew such cases: 215 s
  // for this test). The steps per photon are bounded by the dermis' sigma_t / sigma_a (all of a
  // photon's path absorbed; ~10^4 in the heavy case above); photons = budget / that bound,
  // within 10^5-10^6 (the heavy case: 10^5, ~11 s; a bound of 2300, seed 3: 2.2 x 10^5; most
  // draws' bounds are below 500: 10^6). Fewer photons only leave fewer annuli below 3 % standard
  // error to check, and a wider 3 SE: the check stays what it says.
  constexpr double kStepBudget = 5e8;
  std::vector<mc::CaseResult> results;
  for (const auto& c : cases) {
    const skin::physics::Layer& d = c.stack.layers.back();
    const double steps = (d.sigma_a + d.sigma_s()) / std::max(d.sigma_a, 1e-9);
    o.photons = static_cast<std::uint64_t>(std::clamp(kStepBudget / steps, 1e5, 1e6));
    std::cout << c.id << ": " << o.photons << " photons (dermis sigma_t / sigma_a " << steps << ")\n";
    mc::ValidationRun one = mc::run_validation(
        {c}, {mc::solver_column(skin::transport::find_model("multipole")),
              mc::solver_column(skin::transport::find_model("accurate"))},
        o);
    results.push_back(std::move(one.cases.front()));
  }
  int checked = 0, multipole_failing = 0;
  for (const auto& c : results) {
    const auto pc = c.check_domain(1);
    checked += pc.checked;
    EXPECT_EQ(pc.beyond, 0) << "seed " << seed << ", " << c.c.title << ": " << pc.beyond << " of "
                            << pc.checked << " annuli beyond 5 % + 3 SE, worst " << 100 * pc.worst
                            << " % at " << pc.worst_r << " mm";
    EXPECT_TRUE(c.rd_within(1)) << "seed " << seed << ", " << c.c.title << ": R_d " << c.R_d[1]
                                << ", Monte Carlo " << c.mc.R_d << " +- " << c.mc.R_d_se;
    multipole_failing += c.check_domain(0).beyond > 0 || !c.rd_within(0);
  }
  EXPECT_GT(checked, 0) << "seed " << seed;
  EXPECT_GE(multipole_failing, 2) << "seed " << seed;
}

// The domain's cases and report: valid stacks inside the domain, ids unique, and a report with
// its summary, four maps and a row per case (cheap: the multipole and 2000 photons).
TEST(ValidationReport, DomainReportHasItsSummaryMapsAndCases) {
  const auto cases = mc::domain_cases(6, 3);
  std::set<std::string> ids;
  for (const auto& c : cases) {
    EXPECT_NO_THROW(c.stack.validate()) << c;
    ASSERT_TRUE(c.parameters.has_value());
    EXPECT_TRUE(skin::physics::outside_skin_domain(*c.parameters).empty()) << c;
    EXPECT_GE(c.wavelength, 380);
    EXPECT_LE(c.wavelength, 780);
    ids.insert(c.id);
  }
  EXPECT_EQ(ids.size(), cases.size());
  EXPECT_EQ(mc::domain_cases(6, 3)[5].title, cases[5].title);
  mc::Options o;
  o.photons = 2000;
  o.bins = 50;
  const auto run = mc::run_validation(
      {cases[0], cases[1]}, {mc::solver_column(skin::transport::find_model("multipole"))}, o);
  const skin::test::TempDir dir("skin_domain_report");
  std::ostringstream md;
  EXPECT_EQ(skin::cli::write_domain_report(md, run, dir.path().string(), 3), 2u);
  const std::string text = md.str();
  EXPECT_NE(text.find("--domain 2 --domain-seed 3"), std::string::npos);
  EXPECT_NE(text.find("| multipole | "), std::string::npos);
  EXPECT_NE(text.find(cases[1].title), std::string::npos);
  for (const char* f : {"domain_thickness_melanin.png", "domain_g_eta.png",
                        "domain_wavelength_melanin.png", "domain_wavelength_blood.png"})
    EXPECT_TRUE(std::filesystem::exists(dir.path() / f)) << f;
}
