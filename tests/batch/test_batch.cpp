// skin::batch: every set computed by the single call's code, so the results are the single
// calls' bit for bit, in the order of the sets, for any number of threads.
#include <gtest/gtest.h>

#include "skin/batch/batch.hpp"
#include "skin/batch/sets.hpp"
#include "skin/util/table.hpp"
#include "skin/util/error.hpp"

using namespace skin;
using skin::util::InputError;
using skin::util::Table;
using skin::util::parse_csv;
using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::transport::RgbProfile;
using skin::model::SkinSpectrum;
using skin::model::skin_rgb_profile;
using skin::model::skin_spectral_profile;
using skin::model::skin_spectrum;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

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

// The sets of a batch run (skin/batch/sets.hpp).
TEST(BatchSets, SweepsRunFromStartToStopExactly) {
  // 0.001 + (0.2 - 0.001) rounds to 0.19999999999999998: the last value must be STOP itself.
  const batch::Sweep s = batch::parse_sweep("hemoglobin=0.001:0.2:7");
  EXPECT_EQ(s.count, 7u);
  EXPECT_EQ(s[0], 0.001);
  EXPECT_EQ(s[6], 0.2);
  EXPECT_EQ(batch::parse_sweep("melanin=0:0.5:21")[7], 0.175);  // the decimal a user types
  EXPECT_EQ(batch::parse_sweep("C_m=0.1:0.3:1")[0], 0.1);       // symbols; COUNT 1 is START
}

TEST(BatchSets, GridIsRowMajorOverTheSweeps) {
  const std::vector<batch::Sweep> sweeps = {batch::parse_sweep("melanin=0:0.2:3"),
                                            batch::parse_sweep("hemoglobin=0.01:0.02:2")};
  const batch::Sets sets = batch::sets_from_sweeps(sweeps, SkinParameters{});
  ASSERT_EQ(sets.count, 6u);
  EXPECT_EQ(sets.at(0).melanin, 0.0);
  EXPECT_EQ(sets.at(1).hemoglobin, 0.02);  // the last sweep varies fastest
  EXPECT_EQ(sets.at(2).melanin, 0.1);
  EXPECT_EQ(sets.at(5).melanin, 0.2);
  EXPECT_THROW(batch::sets_from_sweeps({sweeps[0], sweeps[0]}, SkinParameters{}), InputError);
}

TEST(BatchSets, TablesAndRowsAreChecked) {
  const Table t = parse_csv("melanin,C_h\n0.1,\n0.2,0.03\n", "sets.csv");
  const batch::Sets sets = batch::sets_from_table(t, SkinParameters{});
  ASSERT_EQ(sets.count, 2u);
  EXPECT_EQ(sets.at(0).hemoglobin, SkinParameters{}.hemoglobin);  // empty cell: the base value
  EXPECT_EQ(sets.at(1).hemoglobin, 0.03);
  EXPECT_THROW(batch::sets_from_table(parse_csv("melanin,C_m\n0.1,0.1\n", "x.csv"), {}), InputError);
  EXPECT_THROW(batch::sets_from_table(parse_csv("melanin\n2\n", "x.csv"), {}).validate(0, 1), InputError);
  EXPECT_EQ(batch::parse_rows("5:100", 10), (std::pair<std::size_t, std::size_t>{5, 10}));
  for (const char* bad : {"5", "a:3", "4:2", "-1:3", "1.5:3", "1:1e16"})
    EXPECT_THROW(batch::parse_rows(bad, 10), InputError) << bad;
  for (const char* bad : {"melanin=0:1", "melanin=0:1:0", "melanin=0:2:3", "nope=0:1:2", "melanin=0:x:2"})
    EXPECT_THROW(batch::parse_sweep(bad), InputError) << bad;
}
