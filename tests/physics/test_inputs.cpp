// Input validation: every bad value names the parameter, its value and the allowed range.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "skin/util/error.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/transport/stack.hpp"
#include "skin/util/table.hpp"

using namespace skin;
using skin::util::InputError;
using skin::util::Table;
using skin::util::parse_csv;
using skin::util::read_csv_file;
using skin::transport::DiffusionStack;
using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;
using skin::physics::kDefaultPreset;
using skin::physics::kInfinity;
using skin::physics::outside_skin_domain;
using skin::physics::parameter_info;
using skin::physics::parameter_table;
using skin::physics::presets;
using skin::physics::sample_skin_domain;

namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST(Inputs, ParametersOutOfRange) {
  SkinParameters p;
  p.melanin = 1.5;
  EXPECT_EQ(message_of([&] { p.validate(); }),
            "melanin (C_m) = 1.5 is out of range: allowed range is [0, 1]");
  p = {};
  p.hemoglobin = std::nan("");
  EXPECT_EQ(message_of([&] { p.validate(); }),
            "hemoglobin (C_h) = nan is out of range: allowed range is [0, 1]");
  p = {};
  p.epidermis_thickness = -0.1;
  EXPECT_EQ(message_of([&] { p.validate(); }),
            "epidermis-thickness = -0.1 mm is out of range: must be a finite number > 0");
}

TEST(Inputs, LayerStacks) {
  LayerStack s;
  EXPECT_NE(message_of([&] { s.validate(); }).find("empty"), std::string::npos);
  s.layers = {{0.1, 1.0, kInfinity, 1.4}, {0.1, 1.0, 1.0, 1.4}};
  EXPECT_EQ(message_of([&] { s.validate(); }),
            "layer 1 thickness = inf is out of range: only the last layer may be semi-infinite "
            "(give a thickness in mm)");
  s.layers = {{-0.1, 1.0, 1.0, 1.4}};
  EXPECT_EQ(message_of([&] { s.validate(); }),
            "layer 1 sigma_a = -0.1 1/mm is out of range: must be a finite number >= 0");
  s.layers = {{0.1, 0.0, 1.0, 1.4}};
  EXPECT_NE(message_of([&] { DiffusionStack d(s); }).find("layer 1 sigma_s_prime = 0"), std::string::npos);
  s.layers = {{0.1, 1.0, std::numeric_limits<double>::infinity(), 1.4}};
  EXPECT_EQ(message_of([&] { s.validate(); }), "(no error)");
}

TEST(Inputs, PresetsAndGrids) {
  EXPECT_NE(message_of([] { find_preset("martian"); }).find("known presets are caucasian"), std::string::npos);
  EXPECT_EQ(&find_preset("several-lights"), &find_preset("ear"));
  // The default preset exists and is the default-constructed parameters (what a command without
  // --preset and a library call without parameters both mean).
  EXPECT_EQ(find_preset(kDefaultPreset).parameters, SkinParameters{});
  EXPECT_NE(message_of([] { WavelengthGrid(400, 700, 7); }).find("whole number"), std::string::npos);
  EXPECT_NE(message_of([] { WavelengthGrid(700, 400, 2); }).find("lambda_max"), std::string::npos);
  EXPECT_EQ(WavelengthGrid().size(), 151u);
}

TEST(Inputs, CsvParsing) {
  const Table t = parse_csv("# comment\nlambda,R\n400,0.5\n\n402, 0.25\n", "x.csv");
  EXPECT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.data[1][1], 0.25);
  EXPECT_EQ(message_of([] { parse_csv("a,b\n1,2,3\n", "y.csv"); }),
            "y.csv:2: expected 2 comma-separated fields, found 3");
  EXPECT_EQ(message_of([] { parse_csv("a,b\n1,zz\n", "y.csv"); }),
            "y.csv:2: field 2 ('zz') is not a number");
  EXPECT_EQ(message_of([] { parse_csv("# only comments\n", "z.csv"); }),
            "z.csv: no header line (column names) found");
  EXPECT_EQ(message_of([] { read_csv_file("/nonexistent/file.csv"); }),
            "CSV file = '/nonexistent/file.csv': file not found");
}

// The parameter table is complete (one row per member of SkinParameters, each member once),
// its defaults are those of SkinParameters and inside their ranges, and every spelling finds
// its row.
TEST(ParameterTable, CoversEveryMemberOnceWithValidDefaults) {
  const auto table = skin::physics::parameter_table();
  // SkinParameters holds only doubles (and functions): its size counts the members.
  EXPECT_EQ(table.size() * sizeof(double), sizeof(skin::physics::SkinParameters));
  for (std::size_t i = 0; i < table.size(); ++i) {
    for (std::size_t j = i + 1; j < table.size(); ++j) {
      EXPECT_NE(table[i].member, table[j].member) << table[i].key << " and " << table[j].key;
      EXPECT_NE(table[i].key, table[j].key);
    }
    const auto& p = table[i];
    EXPECT_TRUE(p.in_range(p.default_value())) << p.key;
    EXPECT_EQ(skin::physics::find_parameter(p.key), &p);
    EXPECT_EQ(skin::physics::find_parameter(p.flag()), &p);
    if (!p.symbol.empty()) {
      EXPECT_EQ(skin::physics::find_parameter(p.symbol), &p);
    }
    EXPECT_FALSE(p.in_range(std::nan(""))) << p.key;
    EXPECT_THROW(p.check(p.min_open ? p.min : p.min - 1.0), skin::util::InputError) << p.key;
  }
  EXPECT_EQ(skin::physics::find_parameter("beta_m")->key, "melanin_blend");
  EXPECT_EQ(skin::physics::find_parameter("colour"), nullptr);
  EXPECT_THROW(skin::physics::parameter_info("colour"), skin::util::InputError);
}

// The skin domain (issue 31): inside every parameter's allowed range, the paper's presets and the
// defaults inside it, and the values.
TEST(SkinDomain, InsideTheAllowedRangesAndHoldsThePresets) {
  for (const auto& info : parameter_table()) {
    EXPECT_TRUE(info.in_range(info.domain_min)) << info.key;
    EXPECT_TRUE(info.in_range(info.domain_max)) << info.key;
    EXPECT_LT(info.domain_min, info.domain_max) << info.key;
  }
  EXPECT_TRUE(outside_skin_domain(SkinParameters{}).empty());
  for (const auto& p : presets())
    EXPECT_TRUE(outside_skin_domain(p.parameters).empty()) << p.name;
  auto domain = [](std::string_view key) {
    const auto& i = parameter_info(key);
    return std::pair{i.domain_min, i.domain_max};
  };
  EXPECT_EQ(domain("melanin"), std::pair(0.0, 0.5));
  EXPECT_EQ(domain("hemoglobin"), std::pair(0.0, 0.3));
  EXPECT_EQ(domain("epidermis_thickness"), std::pair(0.02, 0.5));
  EXPECT_EQ(domain("dermis_scattering_scale"), std::pair(0.2, 2.0));
  EXPECT_EQ(domain("scattering_scale"), std::pair(0.25, 4.0));
  EXPECT_EQ(domain("g"), std::pair(0.7, 0.97));
  EXPECT_EQ(domain("eta"), std::pair(1.33, 1.55));
  SkinParameters p;
  p.g = 0.6;
  p.epidermis_thickness = 0.01;
  const auto out = outside_skin_domain(p);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0], "epidermis-thickness = 0.01 mm (skin domain [0.02, 0.5])");
  EXPECT_EQ(out[1], "g = 0.6 (skin domain [0.7, 0.97])");
}

// The draw: the same sets for the same seed, inside the domain, both edges of every parameter
// reached, the interior too (1 - 2 x 7/8^400 of the edges missing would fail: never).
TEST(SkinDomain, SamplesAreReproducibleInsideAndReachEveryEdge) {
  const auto a = sample_skin_domain(400, 42), b = sample_skin_domain(400, 42);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, sample_skin_domain(400, 43));
  // Every draw is a parameter set the model accepts (the epidermis' melanin and blood fractions
  // add up to at most 1): with the epidermal blood drawn over [0, 1], 29 % were not.
  for (const auto& p : a) EXPECT_NO_THROW(p.validate()) << p;
  for (const auto& info : parameter_table()) {
    if (!info.sampled) {  // kept at its default (blood_vessel_radius)
      for (const auto& p : a) EXPECT_EQ(p.*(info.member), info.default_value()) << info.key;
      continue;
    }
    int lo = 0, hi = 0, inside = 0;
    for (const auto& p : a) {
      const double v = p.*(info.member);
      ASSERT_TRUE(info.in_domain(v)) << info.key << " " << v;
      lo += v == info.domain_min;
      hi += v == info.domain_max;
      inside += v > info.domain_min && v < info.domain_max;
    }
    EXPECT_GT(lo, 20) << info.key;
    EXPECT_GT(hi, 20) << info.key;
    EXPECT_GT(inside, 250) << info.key;
  }
  // A thickness drawn uniformly in its logarithm: about half below the geometric mean 0.1 mm.
  int thin = 0, interior = 0;
  for (const auto& p : a)
    if (p.epidermis_thickness > 0.02 && p.epidermis_thickness < 0.5) {
      ++interior;
      thin += p.epidermis_thickness < 0.1;
    }
  EXPECT_NEAR(static_cast<double>(thin) / interior, 0.5, 0.1);
}
