// `skin figure` (include/skin/render/figure.hpp): every figure builds its cells on spheres and on
// the head mesh and renders a tiny grid; each cell carries the parameters of the paper's sweep
// as model-notes section 7 lists them (written out here, not taken from the code); the command
// line's parameter changes keep each sweep's own parameter.
#include <gtest/gtest.h>
#include <unistd.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "skin/render/figure.hpp"
#include "skin/util/error.hpp"
#include "skin_test_paths.hpp"

namespace skin::render {

using skin::util::InputError;

using skin::physics::SkinParameters;

namespace {

const std::string kHead = std::string(SKIN_SHARED_DATA_DIR) + "/meshes/LeePerrySmith/LeePerrySmith.glb";

// C_m, beta_m, C_h, rho_s of each cell, row-major (model-notes section 7; DJ06 captions).
struct Four {
  double C_m, beta_m, C_h, rho_s;
};
std::vector<Four> paper_cells(int number) {
  std::vector<Four> v;
  switch (number) {
    case 3:
      for (double x : {0.001, 0.01, 0.05, 0.1, 0.25, 0.5}) v.push_back({x, 0.7, 0.005, 0.5});
      break;
    case 4:
      for (double x : {0.001, 0.005, 0.01, 0.05, 0.1, 0.2}) v.push_back({0.01, 0.5, x, 0.5});
      break;
    case 5:
      for (double x : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) v.push_back({0.5, x, 0.001, 0.5});
      break;
    case 6:
      for (double x : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) v.push_back({0.005, 0.7, 0.005, x});
      break;
    case 7: {
      const double bm[] = {1, 0.7, 0.3, 0}, ch[] = {0.001, 0.01, 0.05, 0.1};
      for (int r = 0; r < 4; ++r)
        for (double cm : {0.001, 0.005, 0.03, 0.2, 0.5}) v.push_back({cm, bm[r], ch[r], 0.4});
      break;
    }
    case 8:
      v = {{0.005, 0.7, 0.005, 0.3}, {0.15, 0.0, 0.01, 0.3}, {0.5, 0.7, 0.05, 0.3}};
      break;
    case 10:  // pale, tanned, the ear (back-lit), the ear (several lights)
      v = {{0.003, 0.25, 0.005, 0.3}, {0.02, 0.25, 0.001, 0.25}, {0.002, 0.5, 0.01, 0.25}, {0.002, 0.5, 0.01, 0.25}};
      break;
    default:
      break;
  }
  return v;
}

TEST(Figure, CellsCarryThePapersParameters) {
  for (int n : figure_numbers()) {
    const FigureLayout f = figure_layout(n);
    const auto want = paper_cells(n);
    // Fig. 8 shows three tone presets after the paper's three (checked in the test below).
    const std::size_t cells = want.size() + (n == 8 ? 3 : 0);
    ASSERT_EQ(f.parameters.size(), cells) << "Fig. " << n;
    ASSERT_EQ(f.labels.size(), cells) << "Fig. " << n;
    EXPECT_GE(f.rows * f.columns, static_cast<int>(cells));
    EXPECT_LT(f.columns * (f.rows - 1), static_cast<int>(cells)) << "no empty row";
    for (std::size_t i = 0; i < want.size(); ++i) {
      SCOPED_TRACE("Fig. " + std::to_string(n) + ", cell " + f.labels[i]);
      EXPECT_DOUBLE_EQ(f.parameters[i].melanin, want[i].C_m);
      EXPECT_DOUBLE_EQ(f.parameters[i].melanin_blend, want[i].beta_m);
      EXPECT_DOUBLE_EQ(f.parameters[i].hemoglobin, want[i].C_h);
      EXPECT_DOUBLE_EQ(f.parameters[i].oiliness, want[i].rho_s);
    }
  }
  EXPECT_EQ(figure_layout(7).columns, 5);
  EXPECT_EQ(figure_layout(7).rows, 4);
  EXPECT_EQ(figure_layout(3).title, "Fig. 3: melanin fraction C_m (beta_m 0.7, C_h 0.5%, rho_s 0.5)");
  EXPECT_THROW(figure_layout(9), InputError);
  EXPECT_THROW(figure_layout(2), InputError);
}

TEST(Figure, ParameterChangesKeepTheSweptParameter) {
  // --preset african on Fig. 6: African skin, oiliness still swept 0..1.
  SkinParameters african;
  african.melanin = 0.5;
  african.melanin_blend = 0.7;
  african.hemoglobin = 0.05;
  african.oiliness = 0.3;
  const FigureLayout f = figure_layout(6, [&](const SkinParameters&) { return african; });
  ASSERT_EQ(f.parameters.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_DOUBLE_EQ(f.parameters[i].melanin, 0.5);
    EXPECT_DOUBLE_EQ(f.parameters[i].hemoglobin, 0.05);
    EXPECT_DOUBLE_EQ(f.parameters[i].oiliness, 0.2 * static_cast<double>(i));
  }
  EXPECT_EQ(f.title, "Fig. 6: oiliness rho_s (C_m 50%, beta_m 0.7, C_h 5%, sigma 0.35)");
  // Fig. 8 has no sweep: a change applies to every cell.
  const FigureLayout g = figure_layout(8, [](SkinParameters p) {
    p.oiliness = 0.6;
    return p;
  });
  for (const auto& p : g.parameters) EXPECT_DOUBLE_EQ(p.oiliness, 0.6);
}

// Every figure renders a grid of 3 x 2 pixels per cell at 1 spp: sizes, finite values, skin seen.
void expect_tiny_render(int number, const std::string& mesh) {
  SCOPED_TRACE("Fig. " + std::to_string(number) + (mesh.empty() ? " on spheres" : " on the mesh"));
  const Figure fig = make_figure(number, mesh);
  ASSERT_EQ(fig.cells.size(), fig.layout.labels.size());
  EXPECT_EQ(fig.on_mesh, !mesh.empty());
  RenderSettings rs;
  rs.width = 3;
  rs.height = 2;
  rs.spp = 1;
  rs.threads = 1;
  RenderStats st;
  const Image img = render_figure(fig, rs, &st);
  ASSERT_EQ(img.width, 3 * fig.layout.columns);
  ASSERT_EQ(img.height, 2 * fig.layout.rows);
  EXPECT_EQ(st.camera_samples, 6u * fig.cells.size());
  EXPECT_EQ(st.skin_mask.size(), static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height));
  EXPECT_EQ(st.invalid_samples, 0u);
  EXPECT_GT(st.skin_pixels, 0u) << "the camera sees skin in the middle of the cells";
  // (One sample of a pixel may be slightly negative: the sRGB profiles dip below zero at a few
  // mm, docs/renderer.md; the sum is not.)
  double sum = 0;
  for (float v : img.rgb) {
    EXPECT_TRUE(std::isfinite(v));
    sum += v;
  }
  EXPECT_GT(sum, 0);
  const Image labelled = annotate_figure(img, fig.layout);
  EXPECT_EQ(labelled.width, img.width);
  EXPECT_GT(labelled.height, img.height);
}

TEST(Figure, EveryFigureRendersOnSpheres) {
  for (int n : figure_numbers()) expect_tiny_render(n, "");
  expect_tiny_render(kTonesFigure, "");
}

TEST(Figure, EveryFigureRendersOnTheHead) {
  if (!std::filesystem::exists(kHead)) GTEST_SKIP() << "no head mesh at " << kHead;
  for (int n : figure_numbers()) expect_tiny_render(n, kHead);
  expect_tiny_render(kTonesFigure, kHead);
}

TEST(Figure, Fig8ShowsThePapersTypesAboveToneRangeAndTonesFigureTheTenPresets) {
  // Fig. 8: the paper's three skin types (as the paper gives them), then three tone presets of the
  // same span; the tones figure: monk-01 ... monk-10, their committed values, two rows of five.
  const FigureLayout f = figure_layout(8);
  ASSERT_EQ(f.labels, (std::vector<std::string>{"caucasian", "asian", "african", "monk-02", "monk-06", "monk-10"}));
  EXPECT_EQ(f.columns, 3);
  EXPECT_EQ(f.rows, 2);
  for (std::size_t i = 0; i < f.labels.size(); ++i)
    EXPECT_DOUBLE_EQ(f.parameters[i].melanin, skin::physics::find_preset(f.labels[i]).parameters.melanin) << f.labels[i];
  const FigureLayout t = figure_layout(kTonesFigure);
  ASSERT_EQ(t.labels.size(), 10u);
  EXPECT_EQ(t.labels.front(), "monk-01");
  EXPECT_EQ(t.labels.back(), "monk-10");
  EXPECT_EQ(t.columns, 5);
  EXPECT_EQ(t.rows, 2);
  for (std::size_t i = 0; i < t.labels.size(); ++i)
    EXPECT_DOUBLE_EQ(t.parameters[i].hemoglobin, skin::physics::find_preset(t.labels[i]).parameters.hemoglobin) << t.labels[i];
}

// Without ../shared/data (a fresh directory), `skin figure` renders spheres and says so in one
// line; --mesh naming a missing file is an error (exit 2, nothing written).
TEST(Figure, CommandFallsBackToSpheresWithANote) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("skin_figure_" + std::to_string(::getpid()));
  fs::create_directories(dir / "work");
  const auto run = [&](const std::string& args, std::string* err) {
    const std::string cmd = "cd '" + (dir / "work").string() + "' && '" SKIN_BINARY "' figure " + args +
                            " > /dev/null 2> ../err.txt";
    const int status = std::system(cmd.c_str());
    std::stringstream ss;
    ss << std::ifstream(dir / "err.txt").rdbuf();
    *err = ss.str();
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  std::string err;
  EXPECT_EQ(run("8 --resolution 2x2 --spp 1 -o f.png", &err), 0) << err;
  EXPECT_NE(err.find("note: no head mesh at ../shared/data/meshes/LeePerrySmith/LeePerrySmith.glb: rendering spheres"),
            std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_TRUE(fs::exists(dir / "work" / "f.png"));
  EXPECT_EQ(run("8 --mesh absent.glb --resolution 2x2 --spp 1 -o g.png", &err), 2) << err;
  EXPECT_NE(err.find("absent.glb"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "work" / "g.png"));
  fs::remove_all(dir);
}

TEST(Figure, AMissingMeshIsAnInputError) {
  EXPECT_THROW(make_figure(8, "no-such-head.glb"), InputError);
}

}  // namespace
}  // namespace skin::render
