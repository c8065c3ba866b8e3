// Describe, then build (include/skin/render/scene.hpp): the edits of a SceneDescription (the
// CLI's flags, `skin figure`) give the scene the file would give with the same values, and the
// build computes each distinct skin once, over all the descriptions built together.
#include <gtest/gtest.h>

#include <string>

#include "scene_data.hpp"
#include "scene_impl.hpp"
#include "skin/render/figure.hpp"
#include "skin/render/scene.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

using skin::util::InputError;

using skin::physics::SkinParameters;
using skin::physics::find_preset;

namespace {

// A scene of the given materials (JSON object members), one sphere each.
std::string scene_of(const std::string& materials, int count, const std::string& render = "{}") {
  std::string objects;
  const char* names[] = {"a", "b", "c"};
  for (int i = 0; i < count; ++i)
    objects += std::string(i ? "," : "") + R"({"sphere": {"center":[)" + std::to_string(3 * i) +
               R"(,0,0], "radius":1}, "material": ")" + names[i] + "\"}";
  return R"({"camera": {"eye":[0,0,9], "look_at":[0,0,0]}, "render": )" + render + R"(, "materials": {)" + materials +
         R"(}, "objects": [)" + objects + "]}";
}

const TranslucentMaterial& translucent(const Scene& s, std::size_t i) {
  const TranslucentMaterial* t = s.impl().data.materials.at(i).translucent();
  EXPECT_NE(t, nullptr);
  return *t;
}

TEST(SceneDescription, EditsGiveTheSceneOfTheSameValues) {
  // --preset african, a parameter flag and --solver on the description: the same profiles as
  // a file that says so.
  SceneDescription d = SceneDescription::parse(scene_of(R"("a": {"type":"skin","preset":"caucasian"})", 1), "", "d");
  d.set_skin_parameters(find_preset("african").parameters);
  d.update_skin_parameters([](SkinParameters p) {
    p.melanin = 0.3;
    return p;
  });
  d.set_solver(transport::find_model("multipole"));
  const Scene edited = d.build();
  const Scene file = Scene::parse(
      scene_of(R"("a": {"type":"skin","preset":"african","melanin":0.3,"solver":"multipole"})", 1), "", "f");
  const TranslucentMaterial &e = translucent(edited, 0), &f = translucent(file, 0);
  EXPECT_EQ(e.solver, f.solver);
  EXPECT_EQ(std::string(e.solver->name()), "multipole");
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(e.R_d[c], f.R_d[c]);
    EXPECT_EQ(e.profile[static_cast<std::size_t>(c)].eval(0.5), f.profile[static_cast<std::size_t>(c)].eval(0.5));
  }
  EXPECT_EQ(e.rho_s, f.rho_s);
  // The caucasian R_d differs: the edit is not a no-op.
  const Scene before = Scene::parse(scene_of(R"("a": {"type":"skin","preset":"caucasian"})", 1), "", "c");
  EXPECT_NE(translucent(before, 0).R_d[0], e.R_d[0]);
}

TEST(SceneDescription, EachDistinctSkinIsComputedOnce) {
  // Spectral: two materials of one skin share their per-wavelength profiles (one computation),
  // a third of another melanin has its own.
  SceneDescription d = SceneDescription::parse(
      scene_of(R"("a": {"type":"skin","preset":"asian"}, "b": {"type":"skin","preset":"asian"},
                  "c": {"type":"skin","preset":"asian","melanin":0.2})",
               3, R"({"spectral": true})"),
      "", "d");
  d.set_solver(transport::find_model("multipole"));
  const Scene s = d.build();
  ASSERT_TRUE(translucent(s, 0).spectral);
  EXPECT_EQ(translucent(s, 0).spectral, translucent(s, 1).spectral);
  EXPECT_NE(translucent(s, 0).spectral, translucent(s, 2).spectral);
  // Over several descriptions built together (a figure's cells): Fig. 10's two ear cells.
  FigureDescription fig = describe_figure(10, "");
  for (auto& cell : fig.cells) {
    cell.set_solver(transport::find_model("multipole"));
    cell.set_spectral(true);
  }
  const Figure built = fig.build();
  ASSERT_EQ(built.cells.size(), 4u);
  EXPECT_EQ(translucent(built.cells[2], 0).spectral, translucent(built.cells[3], 0).spectral);
  EXPECT_NE(translucent(built.cells[0], 0).spectral, translucent(built.cells[2], 0).spectral);
}

TEST(SceneDescription, DiffuseStandInsAndSpectralChecks) {
  const std::string layered = R"("b": {"type":"layered","layers":[{"sigma_a":0.2,"sigma_s_prime":2}]})";
  SceneDescription d =
      SceneDescription::parse(scene_of(R"("a": {"type":"skin","preset":"asian"}, )" + layered, 2), "", "d");
  // A layered material has no spectrum: refused, until it stands in as diffuse.
  EXPECT_THROW(d.set_spectral(true), InputError);
  EXPECT_FALSE(d.spectral());
  const Scene translucent_scene = d.build();
  d.make_translucent_diffuse();
  d.set_spectral(true);
  const Scene s = d.build();
  for (std::size_t i = 0; i < 2; ++i) {
    const auto* diffuse = std::get_if<DiffuseMaterial>(&s.impl().data.materials[i].type);
    ASSERT_NE(diffuse, nullptr);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(diffuse->albedo[c], translucent(translucent_scene, i).R_d[c]);
  }
}

}  // namespace
// What a build will solve is known before it starts (the CLI announces it with an estimate), and
// with a progress callback the solving materials report per profile, in order, to the total;
// the numbers are those of a build without one. A skin on the skin table is read; a layered
// half-space with g = 0.7, brighter (sigma_a / sigma_s' 0.025) than the half-space table's, is
// off the accurate model's tables and solved per channel; the
// multipole solves nothing.
TEST(SceneDescription, BuildWorkCountsTheSolvedProfilesAndProgressReportsThem) {
  const std::string materials =
      R"("a": {"type":"skin","preset":"caucasian"},)"
      R"("b": {"type":"layered","layers":[{"sigma_a":0.05,"sigma_s_prime":2,"g":0.7}]},)"
      R"("c": {"type":"skin","preset":"caucasian","solver":"multipole"})";
  const SceneDescription d = SceneDescription::parse(scene_of(materials, 3), "", "d");
  const BuildWork w = d.build_work();
  EXPECT_EQ(w.profiles, 31u + 3u + 31u);  // two distinct skins on 400-700 nm at 10 nm, three channels
  EXPECT_EQ(w.solved, 3u);
  std::vector<std::pair<std::size_t, std::size_t>> calls;
  const Scene s = d.build([&](std::size_t done, std::size_t total) { calls.emplace_back(done, total); });
  ASSERT_FALSE(calls.empty());
  for (std::size_t i = 0; i < calls.size(); ++i) {
    EXPECT_EQ(calls[i].second, 3u);
    if (i > 0) {
      EXPECT_GE(calls[i].first, calls[i - 1].first);
    }
  }
  EXPECT_EQ(calls.back().first, 3u);
  const Scene plain = d.build();
  for (std::size_t m = 0; m < 3; ++m)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(translucent(s, m).R_d[c], translucent(plain, m).R_d[c]);
      EXPECT_EQ(translucent(s, m).profile[static_cast<std::size_t>(c)].eval(0.3),
                translucent(plain, m).profile[static_cast<std::size_t>(c)].eval(0.3));
    }
  // Without solves nothing is reported.
  calls.clear();
  (void)SceneDescription::parse(scene_of(R"("a": {"type":"skin","preset":"caucasian"})", 1), "", "r")
      .build([&](std::size_t done, std::size_t total) { calls.emplace_back(done, total); });
  EXPECT_TRUE(calls.empty());
}

}  // namespace skin::render
