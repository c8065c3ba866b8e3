// `skin figure N`: the paper's parameter sweeps (model-notes section 7) as a grid of patches,
// each a sphere (or a given mesh) of skin with one parameter set, labelled underneath.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#endif
#include <stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <cstdio>
#include <string>

#include <tbb/parallel_for.h>

#include "scene_impl.hpp"
#include "skin/util/error.hpp"
#include "skin/render/figure.hpp"

namespace skin::render {
namespace {

struct Cell {
  SkinParameters p;
  std::string label;
};

std::string pct(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%g%%", x * 100);
  return b;
}
std::string num(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", x);
  return b;
}

SkinParameters params(double cm, double bm, double ch, double rs) {
  SkinParameters p;
  p.melanin = cm;
  p.melanin_blend = bm;
  p.hemoglobin = ch;
  p.oiliness = rs;
  return p;
}

// The sweeps of DJ06 Figs 3-8 (model-notes section 7).
std::vector<Cell> cells(int number, int* columns, std::string* title) {
  std::vector<Cell> c;
  *columns = 6;
  switch (number) {
    case 3:
      *title = "Fig. 3: melanin fraction C_m (beta_m 0.7, C_h 0.5%, rho_s 0.5)";
      for (double v : {0.001, 0.01, 0.05, 0.1, 0.25, 0.5}) c.push_back({params(v, 0.7, 0.005, 0.5), "C_m " + pct(v)});
      break;
    case 4:
      *title = "Fig. 4: blood fraction C_h (C_m 1%, beta_m 0.5, rho_s 0.5)";
      for (double v : {0.001, 0.005, 0.01, 0.05, 0.1, 0.2}) c.push_back({params(0.01, 0.5, v, 0.5), "C_h " + pct(v)});
      break;
    case 5:
      *title = "Fig. 5: melanin blend beta_m (C_m 50%, C_h 0.1%, rho_s 0.5)";
      for (double v : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) c.push_back({params(0.5, v, 0.001, 0.5), "beta_m " + num(v)});
      break;
    case 6:
      *title = "Fig. 6: oiliness rho_s (Caucasian, sigma 0.35)";
      for (double v : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) c.push_back({params(0.005, 0.7, 0.005, v), "rho_s " + num(v)});
      break;
    case 7:
      *title = "Fig. 7: rows beta_m/C_h = 1/0.1%, 0.7/1%, 0.3/5%, 0/10%; columns C_m (rho_s 0.4)";
      *columns = 5;
      for (auto [bm, ch] : {std::pair{1.0, 0.001}, {0.7, 0.01}, {0.3, 0.05}, {0.0, 0.1}})
        for (double cm : {0.001, 0.005, 0.03, 0.2, 0.5})
          c.push_back({params(cm, bm, ch, 0.4), "C_m " + pct(cm) + " b " + num(bm) + " C_h " + pct(ch)});
      break;
    case 8:
      *title = "Fig. 8: Caucasian, Asian, African";
      *columns = 3;
      for (const char* n : {"caucasian", "asian", "african"}) c.push_back({find_preset(n).parameters, n});
      break;
    default:
      throw InputError("figure = " + std::to_string(number) + " is out of range: one of 3, 4, 5, 6, 7, 8");
  }
  return c;
}

}  // namespace

FigureLayout figure_layout(int number) {
  FigureLayout f;
  const auto c = cells(number, &f.columns, &f.title);
  f.rows = static_cast<int>((c.size() + static_cast<std::size_t>(f.columns) - 1) / static_cast<std::size_t>(f.columns));
  for (const auto& x : c) f.labels.push_back(x.label);
  return f;
}

Scene Scene::figure(int number, const std::string& mesh_path) {
  int columns = 1;
  std::string title;
  const auto list = cells(number, &columns, &title);
  const int rows = static_cast<int>((list.size() + static_cast<std::size_t>(columns) - 1) / static_cast<std::size_t>(columns));
  // Cells 60 mm apart; patches of radius 24 mm (or the mesh scaled to 48 mm high).
  constexpr double kCell = 60, kRadius = 24;
  std::vector<Mesh> proto;
  if (!mesh_path.empty()) {
    proto = load_mesh_file(mesh_path, 0);
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& m : proto)
      for (const auto& p : m.position) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
    const double size = std::max({hi.x - lo.x, hi.y - lo.y, 1e-12});
    const Vec3 mid = (lo + hi) * 0.5;
    for (auto& m : proto)
      for (auto& p : m.position) p = (p - mid) * (2 * kRadius / size);
  }
  SceneData s;
  s.source = "figure " + std::to_string(number);
  // Spheres are 48 mm across; a mesh is drawn 48 units tall at 4 mm per unit (about 190 mm, the
  // height of a head), so that the diffusion profiles act on it at a lifelike scale.
  s.mm_per_unit = proto.empty() ? 1.0 : 4.0;
  s.materials.resize(list.size());
  tbb::parallel_for(std::size_t{0}, list.size(), [&](std::size_t i) {  // independent profiles
    s.materials[i].name = list[i].label;
    prepare_skin_material(s.materials[i], list[i].p);
  });
  for (std::size_t i = 0; i < list.size(); ++i) {
    const int col = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
    const Vec3 centre{(col - (columns - 1) / 2.0) * kCell, ((rows - 1) / 2.0 - row) * kCell, 0};
    if (proto.empty()) {
      s.meshes.push_back(make_sphere(centre, kRadius, 48, 96, i));
    } else {
      for (Mesh m2 : proto) {
        for (auto& p : m2.position) p = p + centre;
        m2.material = i;
        s.meshes.push_back(std::move(m2));
      }
    }
  }
  Material back;
  back.name = "backdrop";
  back.albedo = {0.12, 0.12, 0.12};
  s.materials.push_back(back);
  s.meshes.push_back(make_quad({-1000, -1000, -60}, {2000, 0, 0}, {0, 2000, 0}, s.materials.size() - 1));
  // Orthographic-looking view from far away: each cell is 128 px (160 px for the long labels of
  // Fig. 7).
  const double half_h = rows * kCell / 2;
  const double dist = 2000;
  const int cell_px = number == 7 ? 160 : 128;
  s.camera = {{0, 0, dist}, {0, 0, 0}, {0, 1, 0}, 2 * std::atan(half_h / dist) * 180 / kPi, cell_px * columns, cell_px * rows};
  s.spp = 32;
  s.max_depth = 3;
  // Irradiance about pi x 60 x (120 / 2300)^2 = 0.5.
  s.lights.emplace_back(SphereLight{{-900, 900, 1500}, 120, {60, 60, 60}});
  s.environment.constant = {0.12, 0.12, 0.12};
  return make_scene(std::move(s));
}

Image annotate_figure(const Image& img, const FigureLayout& layout) {
  constexpr int kLabel = 14, kTitle = 18;
  const int cell_w = img.width / layout.columns, cell_h = img.height / layout.rows;
  Image out(img.width, img.height + layout.rows * kLabel + kTitle);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.set(x, y, {0.01, 0.01, 0.01});
  for (int row = 0; row < layout.rows; ++row)
    for (int y = 0; y < cell_h; ++y)
      for (int x = 0; x < img.width; ++x) out.set(x, kTitle + row * (cell_h + kLabel) + y, img.at(x, row * cell_h + y));
  const auto text = [&](int x0, int y0, const std::string& s, int max_w) {
    std::vector<char> buf(s.begin(), s.end());
    buf.push_back('\0');
    std::vector<float> quads(static_cast<std::size_t>(s.size()) * 300);
    const int w = stb_easy_font_width(buf.data());
    const int xs = x0 + std::max(0, (max_w - w) / 2);
    const int n = stb_easy_font_print(static_cast<float>(xs), static_cast<float>(y0), buf.data(), nullptr, quads.data(),
                                      static_cast<int>(quads.size() * sizeof(float)));
    for (int q = 0; q < n; ++q) {
      const float* v = &quads[static_cast<std::size_t>(q) * 16];  // 4 vertices x (x, y, z, colour)
      const int qx0 = static_cast<int>(v[0]), qy0 = static_cast<int>(v[1]);
      const int qx1 = static_cast<int>(v[8]), qy1 = static_cast<int>(v[9]);
      for (int y = qy0; y < qy1; ++y)
        for (int x = qx0; x < qx1; ++x)
          if (x >= 0 && y >= 0 && x < out.width && y < out.height) out.set(x, y, {0.8, 0.8, 0.8});
    }
  };
  text(0, 4, layout.title, out.width);
  for (std::size_t i = 0; i < layout.labels.size(); ++i) {
    const int col = static_cast<int>(i) % layout.columns, row = static_cast<int>(i) / layout.columns;
    text(col * cell_w, kTitle + row * (cell_h + kLabel) + cell_h + 3, layout.labels[i], cell_w);
  }
  return out;
}

}  // namespace skin::render
