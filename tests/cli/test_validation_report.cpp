// The report of `skin validate` (src/app/report_validation.cpp) counts and links only the plots
// it wrote: a case whose Monte Carlo profile has no bin worth plotting (too few photons) gets a
// note, not a link to a missing file (issue 29, item 9: it claimed 21 plots and wrote 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "../temp_dir.hpp"
#include "report_validation.hpp"
#include "skin/mc/validation.hpp"

// The report draws plots with Cairo, whose fontconfig keeps a process-lifetime cache it never
// frees (not a leak of ours): the same LeakSanitizer suppression as the skin binary's (main.cpp).
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig\n"; }
#endif
#endif

namespace {
namespace mc = skin::mc;

TEST(ValidationReport, CountsAndLinksOnlyThePlotsWritten) {
  auto cases = mc::generic_cases();
  const std::vector<mc::ValidationCase> two{cases[3], cases[4]};  // absorbing semi-infinite: fast
  mc::Options o;
  o.photons = 2000;
  o.bins = 20;
  o.threads = 1;
  mc::ValidationRun run =
      mc::run_validation(two, {mc::solver_column(skin::transport::find_model("multipole"))}, o);
  ASSERT_EQ(run.cases.size(), 2u);
  // The second case as too few photons leave it: no bin with a meaningful estimate.
  std::fill(run.cases[1].mc.R.begin(), run.cases[1].mc.R.end(), 0.0);
  const skin::test::TempDir tmp("skin_validation_plots");
  std::ostringstream md;
  const std::size_t plots = skin::cli::write_validation_report(md, run, tmp.path().string(), "plots/");
  std::size_t pngs = 0;
  for (const auto& e : std::filesystem::directory_iterator(tmp.path())) pngs += e.path().extension() == ".png";
  EXPECT_EQ(plots, 2u);  // the overview and the first case
  EXPECT_EQ(pngs, plots);
  const std::string text = md.str();
  std::size_t links = 0;
  for (std::size_t at = text.find("](plots/"); at != std::string::npos; at = text.find("](plots/", at + 1)) {
    const std::string file = text.substr(at + 8, text.find(')', at) - at - 8);
    EXPECT_TRUE(std::filesystem::exists(tmp.path() / file)) << file;
    ++links;
  }
  EXPECT_EQ(links, plots);
  EXPECT_EQ(text.find("profile_" + two[1].id + ".png"), std::string::npos);
  EXPECT_NE(text.find("(No profile plot: no annulus has a Monte Carlo estimate"), std::string::npos);
}

}  // namespace
