// The registry of transport models (skin/transport/model.hpp): names, the default, agreement of
// each model with the class it wraps, and the validity check (the accurate model's transport
// tables, the multipole's z_r), which must say exactly when the accurate profile leaves the
// tables.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "skin/model/skin_model.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/model.hpp"
#include "skin/transport/profile.hpp"
#include "skin/util/error.hpp"

namespace {

using skin::kInfinity;
using skin::Layer;
using skin::LayerStack;
namespace transport = skin::transport;

LayerStack two_layers(Layer top, Layer bottom) {
  LayerStack s;
  s.layers = {top, bottom};
  return s;
}

// Dark over bright: an epidermis-like layer far darker than the tables' darkest node (alpha' =
// 2 / 52 = 0.038 < 0.0975) over a bright half-space.
LayerStack dark_over_bright() {
  return two_layers(Layer{50.0, 2.0, 0.05, 1.4, 0.9}, Layer{0.001, 10.0, kInfinity, 1.4, 0.9});
}

}  // namespace

TEST(ModelRegistry, NamesDefaultAndUnknown) {
  EXPECT_EQ(transport::model_names(), (std::vector<std::string>{"accurate", "multipole", "sfd"}));
  EXPECT_EQ(transport::default_model().name(), transport::kDefaultModel);
  EXPECT_EQ(transport::kDefaultModel, "accurate");
  EXPECT_EQ(transport::find_model("multipole").name(), "multipole");
  try {
    transport::find_model("diffusion");
    FAIL() << "no InputError";
  } catch (const skin::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'diffusion' is unknown"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("accurate, multipole, sfd"), std::string::npos) << e.what();
  }
}

// Each model is the class it wraps, to the last bit (the golden test relies on it).
TEST(ModelRegistry, ModelsAreTheClassesTheyWrap) {
  const LayerStack s = two_layers(Layer{0.5, 5.0, 0.25, 1.4, 0.9}, Layer{0.05, 2.5, 1.0, 1.4, 0.9});
  const auto& acc = transport::find_model("accurate");
  const auto& mp = transport::find_model("multipole");
  const auto ad = skin::accurate::adding_doubling(s);
  EXPECT_EQ(acc.totals(s).R_d, ad.R_d);
  EXPECT_EQ(acc.totals(s).T_d, ad.T_d);
  EXPECT_EQ(acc.R_d(s), ad.R_d);
  const skin::DiffusionStack ds(s);
  EXPECT_EQ(mp.totals(s).R_d, ds.R_d());
  EXPECT_EQ(mp.totals(s).T_d, ds.T_d());
  EXPECT_EQ(mp.totals(s).R_specular, ad.R_specular);  // both the Fresnel reflectance at normal incidence
  skin::ProfileSolver ps(skin::RadialGrid::logarithmic(0.01, 10, 16));
  // The model keeps the Fresnel moments per index; the stack built alone computes them: equal.
  EXPECT_EQ(ps.profile(*acc.response(s)), ps.profile(skin::accurate::AccurateStack(s)));
  EXPECT_EQ(ps.profile(*mp.response(s)), ps.profile(ds));
  EXPECT_THROW(acc.response(LayerStack{}), skin::InputError);
}

TEST(ModelValidity, SkinPresetsAreInsideBothModels) {
  for (const auto& p : skin::presets()) {
    SCOPED_TRACE(p.name);
    for (const char* name : {"accurate", "multipole"}) {
      const auto v = skin::skin_validity(p.parameters, skin::WavelengthGrid(), transport::find_model(name));
      EXPECT_TRUE(v.ok()) << name << " " << v;
    }
  }
}

// Another g: the tables cover g in [0.8, 0.95]; at g = 0.7 the profile is radiative transfer
// in the spatial-frequency domain: the model stays inside its validated range.
TEST(ModelValidity, AccurateOutsideTablesForAnotherG) {
  skin::SkinParameters p = skin::find_preset("caucasian").parameters;
  p.g = 0.7;
  const skin::WavelengthGrid grid(400, 700, 100);
  EXPECT_TRUE(skin::skin_validity(p, grid, transport::find_model("accurate")).ok());
  const auto s = skin::skin_layer_stack(p, 500);
  EXPECT_NE(skin::accurate::transport_table_gap(s).find("g = 0.7"), std::string::npos);
  EXPECT_FALSE(skin::accurate::AccurateStack(s).transport_top());
  // The multipole does not depend on g.
  EXPECT_TRUE(skin::skin_validity(p, grid, transport::find_model("multipole")).ok());
}

// Dark over bright and a thin dark top: thinner than the skin table's thinnest epidermis, so no
// table (the transport top layer's finite layer is not used there), and no complaint.
TEST(ModelValidity, AccurateDarkOverBright) {
  EXPECT_TRUE(transport::find_model("accurate").validity(dark_over_bright()).ok());
  EXPECT_NE(skin::accurate::transport_table_gap(dark_over_bright()).find("is below 0.593"),
            std::string::npos);
  const LayerStack thin = two_layers(Layer{5.0, 2.0, 0.02, 1.4, 0.9}, Layer{0.001, 10.0, kInfinity, 1.4, 0.9});
  EXPECT_TRUE(transport::find_model("accurate").validity(thin).ok());
  EXPECT_NE(skin::accurate::transport_table_gap(thin).find("is below 0.593"), std::string::npos);
  // A half-space under a top with sigma_s' d = 1 and darker than the
  // tables' darkest albedo, and the stack of section 8's "dark over bright" (sigma_s' d = 0.2,
  // thinner than the skin table's 0.59): no table either.
  const LayerStack dark_skin = two_layers(Layer{50.0, 2.0, 0.5, 1.4, 0.9}, Layer{0.001, 1.0, kInfinity, 1.4, 0.9});
  EXPECT_NE(skin::accurate::transport_table_gap(dark_skin).find("alpha' = 0.0385"), std::string::npos);
  const LayerStack sec8 = two_layers(Layer{2.0, 2.0, 0.1, 1.4, 0.9}, Layer{0.01, 1.0, kInfinity, 1.4, 0.9});
  EXPECT_NE(skin::accurate::transport_table_gap(sec8).find("sigma_s' d = 0.2"), std::string::npos);
  EXPECT_FALSE(skin::accurate::AccurateStack(sec8).transport_top());
}

TEST(ModelValidity, MultipoleLayerThinnerThanZr) {
  const auto& mp = transport::find_model("multipole");
  // sigma_t' = 5/mm: z_r = 0.2 mm, thicker than the 0.1 mm layer.
  const LayerStack thin = two_layers(Layer{0.5, 4.5, 0.1, 1.4, 0.9}, Layer{0.05, 2.5, kInfinity, 1.4, 0.9});
  const auto v = mp.validity(thin);
  EXPECT_FALSE(v.totals);
  EXPECT_FALSE(v.profile);
  EXPECT_NE(v.reason.find("layer 1 is thinner than z_r"), std::string::npos) << v;
  LayerStack thick = thin;
  thick.layers[0].thickness = 0.25;
  EXPECT_TRUE(mp.validity(thick).ok());
}

// Over random stacks the accurate model is inside its range (tables or radiative transfer), and
// both kinds of stack occur.
TEST(ModelValidity, AccurateCheckMatchesTheShapeUsed) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto& acc = transport::find_model("accurate");
  int flagged = 0, table = 0;
  for (int i = 0; i < 200; ++i) {
    auto layer = [&](bool last) {
      Layer l;
      l.sigma_s_prime = 0.5 + 10 * u(rng);
      l.sigma_a = l.sigma_s_prime * std::pow(10.0, -3 + 4 * u(rng));
      l.thickness = last && u(rng) < 0.5 ? kInfinity : std::pow(10.0, -2 + 2 * u(rng));
      l.eta = u(rng) < 0.8 ? 1.4 : 1.33;
      const double gs[] = {0.7, 0.8, 0.85, 0.9, 0.95, 0.97};
      l.g = gs[static_cast<int>(u(rng) * 6)];
      return l;
    };
    LayerStack s;
    const int n = 1 + static_cast<int>(u(rng) * 2);
    for (int k = 0; k < n; ++k) s.layers.push_back(layer(k + 1 == n));
    const auto v = acc.validity(s);
    SCOPED_TRACE(::testing::Message() << s << " " << v);
    EXPECT_TRUE(v.ok());
    const bool gap = !skin::accurate::transport_table_gap(s).empty();
    flagged += gap ? 1 : 0;
    table += gap ? 0 : 1;
  }
  // Both kinds occur, so the checks above are exercised.
  EXPECT_GT(flagged, 20);
  EXPECT_GT(table, 20);
}
