// spectral_compare: how far RGB rendering (the paper's method) and spectral rendering differ
// (docs/renderer.md, "Spectral rendering"), and what a spectral sample costs.
//
//   build/bin/spectral_compare [--upsampling | HEAD_SCENE.json [FIGURE.png]]
//
// 0. The RGB -> spectrum basis: its range and round-trip error (alone with --upsampling).
//
// 1. Every preset on a uniformly lit flat slab (rho_s as the preset has it), under D65 and under
//    illuminant A (an environment of luminance 1): CIEDE2000 between the two renders, and of
//    each against `skin color` (R_d under the illuminant; the slab's specular part is the same
//    in both modes).
// 2. A scene (the face of examples/head.json: its field of view narrowed to 13 degrees) in both modes under its own lights and with every
//    light and the environment turned into illuminant A: CIEDE2000 of the skin pixels' mean
//    colour, and the median per-pixel CIEDE2000 next to that of two RGB renders of different
//    seeds (the noise floor); CPU time per camera sample of each mode (one thread, std::clock).
// 3. With FIGURE.png: the four head renders side by side (RGB | spectral; D65 row, A row).
// Colours are compared in CIELAB relative to the illuminant's white (no adaptation: what the
// renders hold).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/render/scene.hpp"
#include "spectral.hpp"  // src/render: the upsampling basis

namespace {
using namespace skin;  // NOLINT(google-build-using-namespace)
using skin::util::Rgb;
using skin::model::skin_spectrum;
using skin::physics::WavelengthGrid;
using skin::physics::presets;
using skin::physics::paper_presets;

// The film's white: the D65 white in linear sRGB that renders divide by.
color::Lab lab_of(const Rgb& rgb, const color::Colorimetry& cm) {
  static const Rgb white = color::xyz_to_srgb_linear(color::Colorimetry(WavelengthGrid()).d65_white());
  return color::xyz_to_lab(color::srgb_linear_to_xyz(rgb * white), cm.white());
}

Rgb mean_of(const render::Image& img, const std::vector<std::uint8_t>* mask) {
  Rgb s;
  double n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (!mask || (*mask)[static_cast<std::size_t>(y * img.width + x)]) {
        s += img.at(x, y);
        n += 1;
      }
  return s / n;
}

struct Timed {
  render::Image image;
  render::RenderStats stats;
  double cpu_s = 0;
};
Timed render_timed(const render::Scene& scene, const render::RenderSettings& rs) {
  Timed t;
  const std::clock_t c0 = std::clock();
  t.image = render::render(scene, rs, &t.stats);
  t.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  return t;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

// The RGB -> spectrum basis: its range, and the round trip under D65 of a 11^3 grid of
// reflectances (the film at 300 stratified wavelengths).
void upsampling() {
  const render::RgbUpsampling& up = render::RgbUpsampling::get();
  const char* names[6] = {"cyan", "magenta", "yellow", "red", "green", "blue"};
  std::printf("upsampling basis (10 nm, 400-700 nm): ");
  for (int k = 0; k < 6; ++k) {
    const auto& b = up.basis(k);
    std::printf("%s [%.3f, %.3f]%s", names[k], *std::min_element(b.begin(), b.end()), *std::max_element(b.begin(), b.end()),
                k < 5 ? ", " : "\n");
  }
  const render::SpectralEmission d65(nullptr);
  double worst = 0;
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 10; ++j)
      for (int k = 0; k <= 10; ++k) {
        const Rgb rgb{i / 10.0, j / 10.0, k / 10.0};
        Rgb c;
        for (int h = 0; h < 75; ++h) {
          const render::SampledWavelengths wl = render::SampledWavelengths::hero((h + 0.5) / 300);
          render::SampledSpectrum v;
          for (int w = 0; w < render::kWavelengths; ++w) {
            const double l = wl.lambda[static_cast<std::size_t>(w)];
            v[w] = up(rgb, l) * d65.spd(l);
          }
          c += render::film_srgb_linear(v, wl) / 75.0;
        }
        for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::abs(c[ch] - rgb[ch]));
      }
  std::printf("round trip under D65 (11^3 reflectances): largest error %.2g\n", worst);
}

void slabs() {
  std::printf("slab (uniform environment of luminance 1), CIEDE2000\n");
  std::printf("%-10s %-4s %12s %14s %14s\n", "preset", "ill.", "RGB-spectral", "RGB-skin color", "spec-skin color");
  for (const auto& preset : paper_presets())
    for (const char* ill : {"D65", "A"}) {
      const color::Colorimetry cm(WavelengthGrid(), color::find_illuminant(ill));
      const color::Lab truth = color::summarize(cm, skin_spectrum(preset.parameters).R_d).lab;
      const std::string js = R"({ "camera": {"eye":[0,100,0], "look_at":[0,0,0], "up":[0,0,-1], "fov": 10, "resolution":[24,24]},
        "materials": {"m": {"type":"skin","preset":")" + preset.name + R"("}},
        "objects": [{"quad": {"corner":[-2000,0,2000], "edge_u":[4000,0,0], "edge_v":[0,0,-4000]}, "material":"m"}],
        "environment": {"radiance": 1, "illuminant": ")" + ill + R"("}, "render": {"spp": 256, "max_depth": 1} })";
      render::SceneDescription scene = render::SceneDescription::parse(js, "", "slab");
      render::RenderSettings rs;
      const Rgb rgb = mean_of(render::render(scene.build(), rs), nullptr);
      scene.set_spectral(true);
      const Rgb spec = mean_of(render::render(scene.build(), rs), nullptr);
      // The slab has a surface term: compare with R_d's colour only where rho_s = 0.
      render::SceneDescription bare = render::SceneDescription::parse(
          replace_all(js, R"("preset":")" + preset.name + "\"", R"("rho_s":0,"preset":")" + preset.name + "\""), "", "slab");
      const Rgb rgb0 = mean_of(render::render(bare.build(), rs), nullptr);
      bare.set_spectral(true);
      const Rgb spec0 = mean_of(render::render(bare.build(), rs), nullptr);
      std::printf("%-10s %-4s %12.2f %14.2f %14.2f\n", preset.name.c_str(), ill,
                  color::delta_e_2000(lab_of(rgb, cm), lab_of(spec, cm)),
                  color::delta_e_2000(lab_of(rgb0, cm), truth), color::delta_e_2000(lab_of(spec0, cm), truth));
    }
}

void scene_comparison(const std::string& path, const std::string& figure, int size, int spp, int threads) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string base = path.substr(0, path.find_last_of('/') + 1);
  // The face: the camera's field of view narrowed to about half (a crop of the full frame).
  const std::string d65 = replace_all(ss.str(), R"("fov": 29)", R"("fov": 13)");
  const std::string a = replace_all(replace_all(d65, R"("type": "sphere")", R"("type": "sphere", "illuminant": "A")"),
                                    R"("environment": {)", R"("environment": {"illuminant": "A", )");
  render::RenderSettings rs;
  rs.width = rs.height = size;
  rs.spp = spp;
  rs.threads = threads;
  render::Image panel(2 * rs.width, 2 * rs.height);
  int row = 0;
  for (const auto& [name, text] : {std::pair<const char*, std::string>{"D65", d65}, {"A", a}}) {
    const color::Colorimetry cm(WavelengthGrid(), color::find_illuminant(name));
    render::SceneDescription description = render::SceneDescription::parse(text, base, path);
    const render::Scene scene = description.build();
    const Timed rgb = render_timed(scene, rs);
    render::RenderSettings other = rs;
    other.seed = 2;
    const Timed rgb2 = render_timed(scene, other);
    description.set_spectral(true);
    const Timed spec = render_timed(description.build(), rs);
    const auto& mask = rgb.stats.skin_mask;
    std::vector<double> de, floor;
    for (int y = 0; y < rs.height; ++y)
      for (int x = 0; x < rs.width; ++x)
        if (mask[static_cast<std::size_t>(y * rs.width + x)]) {
          de.push_back(color::delta_e_2000(lab_of(rgb.image.at(x, y), cm), lab_of(spec.image.at(x, y), cm)));
          floor.push_back(color::delta_e_2000(lab_of(rgb.image.at(x, y), cm), lab_of(rgb2.image.at(x, y), cm)));
        }
    std::nth_element(de.begin(), de.begin() + static_cast<std::ptrdiff_t>(de.size() / 2), de.end());
    std::nth_element(floor.begin(), floor.begin() + static_cast<std::ptrdiff_t>(floor.size() / 2), floor.end());
    const double samples = static_cast<double>(rgb.stats.camera_samples);
    std::printf("%s under %s: skin mean colour CIEDE2000 %.2f; per pixel median %.2f (RGB vs RGB, other seed: %.2f); "
                "CPU per sample RGB %.3g us, spectral %.3g us (x%.2f); estimated error RGB %.3g, spectral %.3g\n",
                path.c_str(), name, color::delta_e_2000(lab_of(mean_of(rgb.image, &mask), cm), lab_of(mean_of(spec.image, &mask), cm)),
                de[de.size() / 2], floor[floor.size() / 2], 1e6 * rgb.cpu_s / samples, 1e6 * spec.cpu_s / samples,
                spec.cpu_s / rgb.cpu_s, rgb.stats.estimated_error, spec.stats.estimated_error);
    for (int y = 0; y < rs.height; ++y)
      for (int x = 0; x < rs.width; ++x) {
        panel.set(x, row * rs.height + y, rgb.image.at(x, y));
        panel.set(rs.width + x, row * rs.height + y, spec.image.at(x, y));
      }
    ++row;
  }
  if (!figure.empty()) render::write_image(figure, panel, 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    upsampling();
    if (argc > 1 && std::string(argv[1]) == "--upsampling") return 0;
    slabs();
    // SCENE [FIGURE [SIZE SPP THREADS]]: the face at SIZE x SIZE pixels per view (default 160),
    // SPP samples per pixel (128), THREADS render threads (1; CPU time is the process's either way).
    const auto arg = [&](int i, int fallback) { return argc > i ? std::stoi(argv[i]) : fallback; };
    if (argc > 1) scene_comparison(argv[1], argc > 2 ? argv[2] : "", arg(3, 160), arg(4, 128), arg(5, 1));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spectral_compare: %s\n", e.what());
    return 2;
  }
  return 0;
}
