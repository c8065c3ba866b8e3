// skin::batch: every set computed by the single call's code, so the results are the single
// calls' bit for bit, in the order of the sets, for any number of threads.
#include <gtest/gtest.h>

#include "skin/batch/batch.hpp"
#include "skin/util/error.hpp"

using namespace skin;

namespace {
std::vector<SkinParameters> sweep(std::size_t n) {
  std::vector<SkinParameters> sets(n);
  for (std::size_t i = 0; i < n; ++i) {
    sets[i].melanin = 0.4 * static_cast<double>(i) / static_cast<double>(n);
    sets[i].hemoglobin = 0.001 + 0.01 * static_cast<double>(i % 3);
  }
  return sets;
}
}  // namespace

TEST(Batch, SpectraEqualTheSingleCallsForAnyThreadCount) {
  const auto sets = sweep(9);
  const WavelengthGrid grid(400, 700, 20);
  for (const std::string solver : {"accurate", "multipole"}) {
    const transport::Model& model = transport::find_model(solver);
    for (int threads : {1, 2, 0}) {
      const auto out = batch::spectra(sets, grid, model, {threads});
      ASSERT_EQ(out.size(), sets.size());
      for (std::size_t i = 0; i < sets.size(); ++i) {
        const SkinSpectrum one = skin_spectrum(sets[i], grid, model);
        EXPECT_EQ(out[i].parameters, sets[i]);
        EXPECT_EQ(out[i].R_d.values, one.R_d.values) << solver << " set " << i << " threads " << threads;
        EXPECT_EQ(out[i].color.hex, one.color.hex);
        EXPECT_EQ(out[i].color.lab.L, one.color.lab.L);
      }
    }
  }
}

TEST(Batch, ProfilesEqualTheSingleCalls) {
  const auto sets = sweep(4);
  const WavelengthGrid grid(400, 700, 50);
  const RadialGrid radii = RadialGrid::logarithmic(0.05, 5, 7);
  const transport::Model& model = transport::default_model();
  const auto rgb = batch::rgb_profiles(sets, grid, radii, model, {2});
  const auto spectral = batch::spectral_profiles(sets, grid, radii, model, {2});
  for (std::size_t i = 0; i < sets.size(); ++i) {
    ProfileSolver solver(radii);
    const RgbProfile one = skin_rgb_profile(sets[i], grid, solver, model);
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(rgb[i].profile.R[c], one.R[c]) << "set " << i;
    EXPECT_EQ(spectral[i].profile.R, skin_spectral_profile(sets[i], grid, solver, model).R);
    EXPECT_TRUE(rgb[i].validity.ok()) << rgb[i].validity;
  }
}

TEST(Batch, InvalidSetsAndThreadCountsAreInputErrors) {
  auto sets = sweep(3);
  sets[2].melanin = 2;
  EXPECT_THROW(batch::spectra(sets, WavelengthGrid(), transport::default_model()), InputError);
  EXPECT_THROW(batch::spectra(sweep(2), WavelengthGrid(), transport::default_model(), {-1}), InputError);
  EXPECT_TRUE(batch::spectra({}, WavelengthGrid(), transport::default_model()).empty());
}
