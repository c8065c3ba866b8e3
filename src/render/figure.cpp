// `skin figure N`: the paper's figures (model-notes section 7) as a grid of cells, each a scene of
// its own: close-up crops of a face for the sweeps (Figs 3-8), the four views of Fig. 10; spheres
// (and a thin fin for the ear) without a mesh. Each cell is labelled underneath.
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

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "scene_impl.hpp"
#include "skin/util/error.hpp"
#include "skin/render/figure.hpp"

namespace skin::render {

using skin::util::InputError;
using skin::util::Rgb;

using skin::physics::SkinParameters;
using skin::physics::find_preset;

namespace {

// The head mesh's frame: the Lee Perry-Smith scan's bounding box is 7.9451 units tall and
// centred at the origin (within 1e-5 units); any mesh is scaled and moved onto that box, so the
// cameras and lights below frame its face. 22 mm per unit, as examples/head.json.
constexpr double kHeadHeight = 7.9450934;
constexpr double kMmPerUnit = 22;

struct CellSpec {
  SkinParameters p;
  std::string label;
  std::vector<double SkinParameters::*> swept;  // the sweep's own parameters (kept under `change`)
};

enum class Rig { crop, face, ear, lights };

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

// The paper's four numbers of `p` other than the swept ones, for the title.
std::string fixed_text(const SkinParameters& p, const std::vector<double SkinParameters::*>& swept) {
  const std::vector<std::pair<double SkinParameters::*, std::string>> shown = {
      {&SkinParameters::melanin, "C_m " + pct(p.melanin)},
      {&SkinParameters::melanin_blend, "beta_m " + num(p.melanin_blend)},
      {&SkinParameters::hemoglobin, "C_h " + pct(p.hemoglobin)},
      {&SkinParameters::oiliness, "rho_s " + num(p.oiliness)}};
  std::string s;
  for (const auto& [m, text] : shown)
    if (std::find(swept.begin(), swept.end(), m) == swept.end()) s += (s.empty() ? "" : ", ") + text;
  return s;
}

// The sweeps of DJ06 Figs 3-8 and the views of Fig. 10 (model-notes section 7), with the
// paper's parameters.
std::vector<CellSpec> cell_specs(int number, int* columns, std::string* title_head) {
  using P = SkinParameters;
  std::vector<CellSpec> c;
  *columns = 6;
  switch (number) {
    case 3:
      *title_head = "Fig. 3: melanin fraction C_m";
      for (double v : {0.001, 0.01, 0.05, 0.1, 0.25, 0.5}) c.push_back({params(v, 0.7, 0.005, 0.5), "C_m " + pct(v), {&P::melanin}});
      break;
    case 4:
      *title_head = "Fig. 4: blood fraction C_h";
      for (double v : {0.001, 0.005, 0.01, 0.05, 0.1, 0.2}) c.push_back({params(0.01, 0.5, v, 0.5), "C_h " + pct(v), {&P::hemoglobin}});
      break;
    case 5:
      *title_head = "Fig. 5: melanin blend beta_m";
      for (double v : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) c.push_back({params(0.5, v, 0.001, 0.5), "beta_m " + num(v), {&P::melanin_blend}});
      break;
    case 6:
      *title_head = "Fig. 6: oiliness rho_s";
      for (double v : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) c.push_back({params(0.005, 0.7, 0.005, v), "rho_s " + num(v), {&P::oiliness}});
      break;
    case 7:
      *title_head = "Fig. 7: rows beta_m/C_h = 1/0.1%, 0.7/1%, 0.3/5%, 0/10%; columns C_m";
      *columns = 5;
      for (auto [bm, ch] : {std::pair{1.0, 0.001}, {0.7, 0.01}, {0.3, 0.05}, {0.0, 0.1}})
        for (double cm : {0.001, 0.005, 0.03, 0.2, 0.5})
          c.push_back({params(cm, bm, ch, 0.4), "C_m " + pct(cm) + " b " + num(bm) + " C_h " + pct(ch),
                       {&P::melanin, &P::melanin_blend, &P::hemoglobin}});
      break;
    case 8:
      // The paper's parameters (tuned by eye under its multipole model; under exact transport
      // african is near black) above tone presets of the same span, light to darkest.
      *title_head = "Fig. 8: the paper's skin types; tone presets below";
      *columns = 3;
      for (const char* n : {"caucasian", "asian", "african", "monk-02", "monk-06", "monk-10"})
        c.push_back({find_preset(n).parameters, n, {}});
      break;
    case kTonesFigure:
      *title_head = "Tone presets: the Monk Skin Tone scale, monk-01 ... monk-10, fitted under D65";
      *columns = 5;
      for (int k = 1; k <= 10; ++k) {
        const std::string n = std::string(k < 10 ? "monk-0" : "monk-") + std::to_string(k);
        c.push_back({find_preset(n).parameters, n, {}});
      }
      break;
    case 10:
      *title_head = "Fig. 10: pale, tanned, the ear lit from behind, several lights";
      *columns = 4;
      c.push_back({find_preset("pale").parameters, "pale Caucasian", {}});
      c.push_back({find_preset("tanned").parameters, "tanned Caucasian", {}});
      c.push_back({find_preset("ear").parameters, "ear, lit from behind", {}});
      c.push_back({find_preset("ear").parameters, "several lights", {}});
      break;
    default:
      throw InputError("figure = " + std::to_string(number) + " is out of range: one of 3, 4, 5, 6, 7, 8, 10, tones");
  }
  return c;
}

Rig rig_of(int number, std::size_t cell) {
  if (number == kTonesFigure) return Rig::face;
  if (number != 10) return Rig::crop;
  return cell < 2 ? Rig::face : cell == 2 ? Rig::ear : Rig::lights;
}

// Camera, lights and backdrop of a cell (head frame, scene units of 22 mm).
void set_up(Rig rig, SceneSetup& s, std::size_t backdrop) {
  switch (rig) {
    case Rig::crop:
      // Cheek and nose from the front right; a warm key light above left whose reflection the
      // cheek and the nose show (the surface term), a weak cool fill from the right.
      s.camera = {{4.0, 0.8, 12.0}, {0.5, 0.5, 1.9}, {0, 1, 0}, 13.0, 128, 128};
      s.lights.emplace_back(SphereLight{{-12, 14, 8}, 3, {70, 67, 63}});
      s.lights.emplace_back(SphereLight{{12, -2, 10}, 4, {3.5, 3.7, 4.1}});
      s.meshes.push_back(make_quad({-60, -60, -12}, {120, 0, 0}, {0, 120, 0}, backdrop));
      s.environment.constant = {0.02, 0.02, 0.02};
      break;
    case Rig::face:  // examples/head.json
      s.camera = {{5.5, 1.5, 17.5}, {0.3, 0.2, 0}, {0, 1, 0}, 29.0, 192, 192};
      s.lights.emplace_back(SphereLight{{14, 10, 16}, 2.5, {30, 27, 24}});
      s.lights.emplace_back(SphereLight{{-18, 4, 10}, 4, {2.4, 2.6, 3.0}});
      s.lights.emplace_back(SphereLight{{-3, 3, -9}, 1.5, {90, 90, 90}});
      s.meshes.push_back(make_quad({-60, -60, -12}, {120, 0, 0}, {0, 120, 0}, backdrop));
      s.environment.constant = {0.03, 0.03, 0.03};
      break;
    case Rig::ear:
      // The right ear from the front right, a small light behind it (hidden by the head) and a
      // dim front light.
      s.camera = {{7.0, 1.6, 5.0}, {1.5, 1.1, -0.4}, {0, 1, 0}, 20.0, 192, 192};
      s.lights.emplace_back(SphereLight{{2.6, 1.4, -2.4}, 0.25, {60, 60, 60}});
      s.lights.emplace_back(SphereLight{{10, 9, 14}, 3, {0.6, 0.56, 0.52}});
      s.meshes.push_back(make_quad({-80, -60, -16}, {160, 0, 0}, {0, 120, 0}, backdrop));
      s.environment.constant = {0.02, 0.02, 0.02};
      break;
    case Rig::lights:  // examples/head-several-lights.json
      s.camera = {{12.0, 1.5, 11.5}, {1.0, 0.6, 0}, {0, 1, 0}, 30.0, 192, 192};
      s.lights.emplace_back(SphereLight{{10, 9, 14}, 3, {4.5, 4.2, 3.9}});
      s.lights.emplace_back(SphereLight{{-16, 3, 12}, 4, {1.2, 1.3, 1.5}});
      s.lights.emplace_back(SphereLight{{4.6, 1.2, -2.6}, 0.5, {700, 680, 660}});
      s.meshes.push_back(make_quad({-80, -60, -16}, {160, 0, 0}, {0, 120, 0}, backdrop));
      s.environment.constant = {0.02, 0.02, 0.02};
      break;
  }
}

// The mesh moved and scaled onto the head frame (its bounding box kHeadHeight tall, centred).
std::vector<Mesh> head_mesh(const std::string& path) {
  std::vector<Mesh> meshes = load_mesh_file(path, 0);
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& m : meshes)
    for (const auto& p : m.position) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  if (!(hi.y > lo.y)) throw InputError("mesh = '" + path + "': has no height (empty or flat in y)");
  const double scale = kHeadHeight / (hi.y - lo.y);
  const Vec3 mid = (lo + hi) * 0.5;
  for (auto& m : meshes)
    for (auto& p : m.position) p = (p - mid) * scale;
  return meshes;
}

}  // namespace

const std::vector<int>& figure_numbers() {
  static const std::vector<int> n{3, 4, 5, 6, 7, 8, 10};
  return n;
}

FigureLayout figure_layout(int number, const std::function<SkinParameters(const SkinParameters&)>& change) {
  FigureLayout f;
  f.number = number;
  std::string head;
  const auto specs = cell_specs(number, &f.columns, &head);
  f.rows = static_cast<int>((specs.size() + static_cast<std::size_t>(f.columns) - 1) / static_cast<std::size_t>(f.columns));
  for (const auto& c : specs) {
    SkinParameters p = change ? change(c.p) : c.p;
    for (auto m : c.swept) p.*m = c.p.*m;
    p.validate();
    f.labels.push_back(c.label);
    f.parameters.push_back(p);
  }
  // Sweeps name the parameters they keep fixed, with the values used.
  f.title = head;
  if (!specs.front().swept.empty()) {
    f.title += " (" + fixed_text(f.parameters.front(), specs.front().swept);
    if (number == 6) f.title += ", sigma " + num(f.parameters.front().roughness);
    f.title += ")";
  }
  return f;
}

FigureDescription describe_figure(int number, const std::string& mesh_path, const std::string& albedo_texture,
                                  const std::function<SkinParameters(const SkinParameters&)>& change) {
  FigureDescription fig;
  fig.layout = figure_layout(number, change);
  fig.on_mesh = !mesh_path.empty();
  const std::vector<Mesh> head = fig.on_mesh ? head_mesh(mesh_path) : std::vector<Mesh>{};
  std::shared_ptr<const Texture> texture;
  if (fig.on_mesh && !albedo_texture.empty()) texture = load_texture(albedo_texture, true);
  for (std::size_t i = 0; i < fig.layout.labels.size(); ++i) {
    const Rig rig = rig_of(number, i);
    auto s = std::make_unique<SceneDescription::Data>();
    s->source = (number == kTonesFigure ? std::string("figure tones") : "figure " + std::to_string(number)) + ", " +
                fig.layout.labels[i];
    s->mm_per_unit = kMmPerUnit;
    s->spp = 32;
    s->max_depth = rig == Rig::crop ? 3 : 4;
    MaterialDescription m = skin_description(fig.layout.parameters[i]);
    m.name = fig.layout.labels[i];
    if (rig != Rig::crop && texture) {
      // The texture's colour where the parameters are caucasian (DJ06 section 3.6), as
      // examples/head.json.
      m.albedo_map = texture;
      m.texture_reference = find_preset("caucasian").parameters;
    }
    s->materials.push_back(std::move(m));
    MaterialDescription back;
    back.name = "backdrop";
    back.albedo = {0.05, 0.05, 0.05};
    s->materials.push_back(back);
    if (fig.on_mesh) {
      s->meshes = head;
    } else if (rig == Rig::crop) {
      s->meshes.push_back(make_sphere({0.5, 0.5, 1.9}, 1.0, 48, 96, 0));  // 44 mm across
    } else {
      // A head-sized sphere and a thin fin (3.5 mm) where the right ear is.
      s->meshes.push_back(make_sphere({0, 0.8, 0}, 1.6, 48, 96, 0));
      s->meshes.push_back(make_ellipsoid({1.9, 1.1, -0.3}, {0.35, 0.6, 0.08}, 32, 64, 0));
    }
    set_up(rig, *s, 1);
    if (number == 7) s->camera.width = s->camera.height = 160;  // room for the long labels
    fig.cells.emplace_back(std::move(s));
  }
  return fig;
}

namespace {
std::vector<const SceneDescription*> cells_of(const FigureDescription& f) {
  std::vector<const SceneDescription*> d;
  for (const SceneDescription& c : f.cells) d.push_back(&c);
  return d;
}
}  // namespace

Figure FigureDescription::build(const util::ProgressCallback& progress) const {
  Figure fig;
  fig.layout = layout;
  fig.on_mesh = on_mesh;
  fig.cells = render::build(cells_of(*this), progress);
  return fig;
}

BuildWork FigureDescription::build_work() const { return render::build_work(cells_of(*this)); }

Figure make_figure(int number, const std::string& mesh_path, const std::string& albedo_texture,
                   const std::function<SkinParameters(const SkinParameters&)>& change) {
  return describe_figure(number, mesh_path, albedo_texture, change).build();
}

Image render_figure(const Figure& figure, const RenderSettings& settings, RenderStats* stats,
                    const Progress& progress) {
  const std::size_t n = figure.cells.size();
  const int columns = figure.layout.columns, rows = figure.layout.rows;
  RenderSettings rs = settings;
  if (settings.time_budget > 0) rs.time_budget = settings.time_budget / static_cast<double>(n);
  Image grid;
  RenderStats total;
  // Samples per pixel of the figure: what every cell took (the fewest of them; they differ under
  // a time budget), or with adaptive sampling the most any pixel took (its bound, "at most").
  const bool adaptive = settings.target_error > 0;
  total.spp_done = adaptive ? 0 : std::numeric_limits<int>::max();
  // For the error over all cells: per cell, skin pixels x the mean variance of a pixel's mean
  // ((E M)^2, E the cell's estimate and M its skin mean) and skin pixels x M.
  double var_sum = 0, mean_sum = 0;
  bool error_known = true;
  for (std::size_t i = 0; i < n; ++i) {
    RenderStats st;
    const Progress cell_progress = progress ? Progress([&progress, i, n](double f) {
      progress((static_cast<double>(i) + f) / static_cast<double>(n));
    })
                                            : Progress();
    const Image img = render(figure.cells[i], rs, &st, cell_progress);
    const int W = img.width, H = img.height;
    if (i == 0) {
      grid = Image(W * columns, H * rows);
      total.skin_mask.assign(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height), 0);
    }
    const int x0 = static_cast<int>(i) % columns * W, y0 = static_cast<int>(i) / columns * H;
    double skin_sum = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const Rgb c = img.at(x, y);
        grid.set(x0 + x, y0 + y, c);
        const std::uint8_t skin = st.skin_mask[static_cast<std::size_t>(y) * W + x];
        total.skin_mask[static_cast<std::size_t>(y0 + y) * static_cast<std::size_t>(grid.width) + (x0 + x)] = skin;
        if (skin) skin_sum += (c.r + c.g + c.b) / 3;
      }
    total.seconds += st.seconds;
    total.spp_done = adaptive ? std::max(total.spp_done, st.spp_done) : std::min(total.spp_done, st.spp_done);
    total.camera_samples += st.camera_samples;
    total.invalid_samples += st.invalid_samples;
    total.skin_pixels += st.skin_pixels;
    if (st.skin_pixels > 0) {
      const double N = static_cast<double>(st.skin_pixels), M = skin_sum / N;
      if (!std::isfinite(st.estimated_error)) error_known = false;
      var_sum += N * (st.estimated_error * M) * (st.estimated_error * M);
      mean_sum += N * M;
    }
  }
  if (total.skin_pixels > 0 && error_known && mean_sum > 0) {
    const double N = static_cast<double>(total.skin_pixels);
    total.estimated_error = std::sqrt(var_sum / N) / (mean_sum / N);
  } else {
    total.estimated_error = std::numeric_limits<double>::quiet_NaN();
  }
  if (stats) *stats = std::move(total);
  return grid;
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
