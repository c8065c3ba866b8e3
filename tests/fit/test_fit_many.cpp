// Many fits at once (include/skin/fit/fit_many.hpp): each result is the single call's, bit for
// bit, on any number of threads; bad input is refused before the first fit, naming the first bad
// target; a bad thread count is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "skin/fit/fit_many.hpp"
#include "skin/util/error.hpp"

#include "test_params.hpp"

using namespace skin::fit;
using skin::util::InputError;

TEST(FitMany, ColoursAreTheSingleCallsBitForBitOnAnyThreads) {
  const ColorFitter fitter(skin_test::multipole_color_options());
  const std::vector<skin::color::Rgb> targets = {
      {0.45, 0.30, 0.22}, {0.20, 0.12, 0.08}, {0.60, 0.45, 0.38}, {0.05, 0.03, 0.02}, {0.33, 0.21, 0.15}};
  for (int threads : {1, 2, 0}) {
    const auto many = fit_colors(fitter, targets, {threads});
    ASSERT_EQ(many.size(), targets.size());
    for (std::size_t i = 0; i < targets.size(); ++i) {
      const ColorFitResult one = fitter.fit(targets[i]);
      SCOPED_TRACE(::testing::Message() << "threads " << threads << ", target " << i);
      EXPECT_EQ(many[i].parameters, one.parameters);
      EXPECT_EQ(many[i].delta_e, one.delta_e);
      EXPECT_EQ(many[i].iterations, one.iterations);
    }
  }
  EXPECT_TRUE(fit_colors(fitter, {}).empty());
}

TEST(FitMany, TheFirstBadTargetIsNamedBeforeAnyFit) {
  const ColorFitter fitter(skin_test::multipole_color_options());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<skin::color::Rgb> targets = {{0.4, 0.3, 0.2}, {0.4, 0.3, 0.2}, {nan, 0.3, 0.2}, {2.0, 0.3, 0.2}};
  try {
    (void)fit_colors(fitter, targets);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("target 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)fit_colors(fitter, std::vector<skin::color::Rgb>{{0.4, 0.3, 0.2}}, {-1}), InputError);
}
