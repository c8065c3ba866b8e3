// skin render / skin figure: pictures of skin from the Monte Carlo renderer (skin::render).
#include <chrono>
#include <cmath>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>

#include "common.hpp"
#include "progress.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"
#include "skin/render/figure.hpp"
#include "skin/render/scene.hpp"

namespace skin::cli {

using skin::util::InputError;
using skin::util::format_number;

using skin::physics::SkinParameters;

namespace {

// The head mesh `skin figure` uses unless --mesh names another: where examples/head.json finds it,
// from the project's directory (../shared/data, as the measured spectra of `skin fit`).
constexpr const char* kDefaultHeadMesh = "../shared/data/meshes/LeePerrySmith/LeePerrySmith.glb";
// Its colour texture (Fig. 10's faces), looked for beside the mesh.
constexpr const char* kHeadTexture = "Map-COL.jpg";

struct RenderOpts {
  std::string scene, output, resolution, mesh, reference, tone_map;
  int spp = 0, max_depth = -1, figure = 0;
  std::string figure_name;  // skin figure's positional: a number, or tones
  RunOptions run;
  double time_budget = 0, exposure = 0, target_error = 0, point_spacing = 0, point_solid_angle = -1;
  std::string subsurface;
  bool exposure_given = false, diffuse = false, spheres = false, spectral = false;
  SolverOption solver;
  ParameterOptions params;  // changes the skin materials (render) or every cell (figure)
};

void parse_resolution(const std::string& s, render::RenderSettings* rs) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 || h < 1 ||
      w > 16384 || h > 16384)
    throw InputError("resolution = '" + s + "' is out of range: must be WxH with each side in [1, 16384]");
  rs->width = w;
  rs->height = h;
}

void check_output(const std::string& path) {
  const std::string ext = util::io::extension(path);
  if (ext != "png" && ext != "exr")
    throw InputError("output = '" + path + "': unknown image format, use .png or .exr");
}

void add_common(CLI::App* sub, RenderOpts* o) {
  o->solver.add_to(*sub);
  sub->add_option("-o,--output", o->output, "Output image: .png (sRGB 8-bit) or .exr (linear float)")->required();
  sub->add_option("--spp", o->spp, "Samples per pixel (default: the scene's)")->check(whole_number(1, 1 << 20));
  o->run.add_to(*sub, "Random seed; same seed, same image at any thread count");
  sub->add_option("--max-depth", o->max_depth, "Path vertices after the camera (default: the scene's)")->check(whole_number(0, 1000));
  sub->add_option("--time-budget", o->time_budget, "Stop after the last whole sample pass within this many seconds (0 = none)");
  sub->add_option("--target-error", o->target_error,
                  "Adaptive sampling: stop each pixel once its estimated standard error is at most this "
                  "fraction of the skin's mean brightness, in [0, 1) (0 = off; --spp is then the most a "
                  "pixel takes, default 65536)");
  sub->add_option("--reference", o->reference,
                  "An .exr of the same scene and size (e.g. many spp): print the relative RMS error of this "
                  "render against it over the skin pixels");
  sub->add_option("--subsurface", o->subsurface,
                  "The subsurface term: probes (probe rays from each exit point) or points (a point cloud "
                  "with its irradiance, summed through an octree; Jensen & Buhler 2002) (default: the scene's, "
                  "else probes)")
      ->check(CLI::IsMember({"probes", "points"}));
  sub->add_option("--point-spacing", o->point_spacing,
                  "With --subsurface points: the cloud's spacing sqrt(area per point) in mm (default: the scene's, "
                  "else 0.5)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--point-solid-angle", o->point_solid_angle,
                  "With --subsurface points: the largest solid angle A_node / d^2 in sr at which a tree node stands "
                  "in for its points (0 = sum every point; default: the scene's, else 0.05)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--spectral", o->spectral,
                "Spectral rendering: hero wavelength (4 per sample, 400-700 nm), per-wavelength profiles, light "
                "spectra (default: the scene's render.spectral, else RGB, the paper's method)");
  sub->add_option("--exposure", o->exposure, "PNG exposure in stops (default: the scene's)")
      ->each([o](const std::string&) { o->exposure_given = true; });
  sub->add_option("--tone-map", o->tone_map,
                  "PNG tone curve: clip (plain sRGB, values above 1 clipped) or filmic (Hable's curve, "
                  "highlights compressed; docs/renderer.md) (default: the scene's, else clip)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            try {
              (void)image::tone_map_from_name(v);
              return {};
            } catch (const InputError&) {
              return "'" + v + "' is not one of clip, filmic";
            }
          },
          "clip|filmic"));
}

// What is rendered: one scene, or the cells of a figure.
struct Target {
  std::vector<const render::Scene*> scenes;
  std::function<render::Image(const render::RenderSettings&, render::RenderStats*, const render::Progress&)> render;
  const render::FigureLayout* layout = nullptr;
};

void run(const RenderOpts& o, const Target& target) {
  const render::Scene& scene = *target.scenes.front();
  const render::FigureLayout* layout = target.layout;
  check_output(o.output);
  render::RenderSettings rs;
  rs.spp = o.spp;
  rs.seed = o.run.seed;
  rs.threads = o.run.threads;
  rs.max_depth = o.max_depth;
  rs.time_budget = o.time_budget;
  rs.target_error = o.target_error;
  if (!o.subsurface.empty())
    rs.subsurface = o.subsurface == "points" ? render::RenderSettings::Subsurface::points
                                             : render::RenderSettings::Subsurface::probes;
  rs.point_spacing = o.point_spacing;
  rs.point_solid_angle = o.point_solid_angle;
  if (!o.resolution.empty()) parse_resolution(o.resolution, &rs);
  if (o.spp < 0) throw InputError("spp = " + std::to_string(o.spp) + " is out of range: must be >= 1");
  std::set<std::string> said;  // a figure's cells share their materials' names: each line once
  for (const render::Scene* sc : target.scenes)
    for (const auto& v : sc->validity())
      warn_validity(transport::find_model(v.solver), v.validity, "material '" + v.material + "'", &said);
  {
    // A time budget bounds the time already, and adaptive sampling without --spp stops at its
    // target, whose sample count is not known beforehand (its bound, 65536 spp, made a useless
    // "28 hours" warning); the memory is checked either way (per cell of a figure: its cells
    // are rendered one after another).
    render::RenderCost cost = render::render_cost(scene, rs);
    cost.samples *= static_cast<double>(target.scenes.size());
    const std::string cells = target.layout ? std::to_string(target.scenes.size()) + " cells of " : "";
    check_request("a render of " + cells + std::to_string(rs.width > 0 ? rs.width : scene.width()) + "x" +
                      std::to_string(rs.height > 0 ? rs.height : scene.height()) + " pixels, " +
                      format_number(cost.samples) + " samples",
                  o.time_budget > 0 || (o.target_error > 0 && o.spp == 0) ? 0.0 : cost.samples,
                  kRenderSamplesPerSecond, rs.threads, cost.bytes);
  }
  // The reference is read before the render: a bad file fails at once.
  std::optional<render::Image> reference;
  if (!o.reference.empty()) {
    if (util::io::extension(o.reference) != "exr")
      throw InputError("reference = '" + o.reference + "': must be an .exr (linear float) image");
    reference = render::read_image(o.reference);
  }
  render::RenderStats stats;
  render::Image img = target.render(rs, &stats, progress_fraction_bar());
  const double reference_error = reference ? render::relative_rms_error(img, *reference, stats.skin_mask) : 0.0;
  // Per rendered pixel (a figure's label band has none).
  const double mean_spp = static_cast<double>(stats.camera_samples) / (static_cast<double>(img.width) * img.height);
  if (layout) img = render::annotate_figure(img, *layout);
  render::write_image(o.output, img, o.exposure_given ? o.exposure : scene.exposure(),
                      o.tone_map.empty() ? scene.tone_map() : image::tone_map_from_name(o.tone_map));
  if (o.target_error > 0)
    std::printf("wrote %s: %dx%d, %.3g spp on average (at most %d), %.1f s (%.3g samples/s)\n", o.output.c_str(),
                img.width, img.height, mean_spp, stats.spp_done, stats.seconds, stats.samples_per_second());
  else
    std::printf("wrote %s: %dx%d, %d spp, %.1f s (%.3g samples/s)\n", o.output.c_str(), img.width, img.height,
                stats.spp_done, stats.seconds, stats.samples_per_second());
  // The error of the skin pixels, estimated from the two replicates of each pixel (and measured against a
  // reference when given): the relative RMS error, render::RenderStats::estimated_error.
  if (stats.skin_pixels > 0 && std::isfinite(stats.estimated_error)) {
    std::printf("skin: %zu pixels, relative RMS error %.3g (estimated)", stats.skin_pixels, stats.estimated_error);
    if (reference) std::printf(", %.3g against %s", reference_error, o.reference.c_str());
    std::printf("\n");
  }
  if (stats.points > 0)
    std::printf("subsurface: %zu points, built in %.1f s (included above); the error estimate leaves out the "
                "cloud's own, which falls with --point-spacing, not with samples (on the head about 0.025 x the "
                "spacing in mm: ~%.2g here; docs/renderer.md)\n",
                stats.points, stats.point_seconds, 0.025 * stats.point_spacing);
  if (stats.invalid_samples > 0)
    std::fprintf(stderr, "skin: warning: %llu non-finite samples dropped\n",
                 static_cast<unsigned long long>(stats.invalid_samples));
}

}  // namespace

void register_render(CLI::App& app) {
  auto o = std::make_shared<RenderOpts>();
  CLI::App* sub = app.add_subcommand(
      "render",
      "Render a scene (docs/scene-format.md) with the spectral skin BSSRDF by Monte Carlo ray tracing; "
      "without SCENE, the built-in scene of the three Fig. 8 skin types and a back-lit ear-like fin");
  sub->add_option("scene", o->scene, "Scene file (JSON); omit for the built-in default scene");
  add_common(sub, o.get());
  o->params.add_to(*sub);
  o->params.preset_option->description(
      "Use this parameter set for every skin material of the scene (parameter flags and --params "
      "then change it; without --preset they change each material's own set)");
  sub->add_option("--resolution", o->resolution, "Image size WxH (default: the scene's)");
  sub->add_flag("--diffuse", o->diffuse, "Replace every translucent material by a diffuse one of the same R_d (comparison)");
  sub->callback([o, sub] {
    check_output(o->output);
    if (!o->resolution.empty()) {
      render::RenderSettings tmp;
      parse_resolution(o->resolution, &tmp);
    }
    // A bad file or parameter fails before the scene loads.
    std::function<SkinParameters(const SkinParameters&)> change;
    if (o->params.given()) (void)(change = o->params.change())(SkinParameters{});
    // The flags edit the scene's description; its build computes each material once.
    render::SceneDescription description =
        o->scene.empty() ? render::SceneDescription::default_scene() : render::SceneDescription::load(o->scene);
    if (change) description.update_skin_parameters(change);
    if (sub->count("--solver") > 0) description.set_solver(o->solver.model());  // else the scene's
    if (o->diffuse) description.make_translucent_diffuse();
    if (o->spectral) description.set_spectral(true);
    // Profiles solved off the skin table take a good part of a second each: said before the build
    // starts, with an estimate, and a bar on a terminal.
    const render::BuildWork work = description.build_work();
    note_profile_solves(work.solved, work.profiles, "profiles (wavelengths and channels of the materials)");
    const render::Scene scene = description.build(work.solved > 0 ? progress_bar("profiles") : util::ProgressCallback{});
    Target t;
    t.scenes = {&scene};
    t.render = [&scene](const render::RenderSettings& rs, render::RenderStats* st, const render::Progress& p) {
      return render::render(scene, rs, st, p);
    };
    run(*o, t);
  });

  auto f = std::make_shared<RenderOpts>();
  CLI::App* fig = app.add_subcommand(
      "figure",
      "Render a figure of the paper: the parameter sweeps of Figs 3-8 as close-ups of the Lee Perry-Smith "
      "face (cheek and nose, one crop per parameter set; Fig. 8 with three tone presets below the paper's "
      "skin types), Fig. 10 as its four views of the head; or tones: the head per tone preset; "
      "spheres when the mesh is absent");
  fig->add_option("number", f->figure_name,
                  "Figure number: 3, 4, 5, 6, 7, 8 or 10; or tones (a face per tone preset, monk-01 ... monk-10)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            std::string allowed;
            for (int n : render::figure_numbers()) {
              if (v == std::to_string(n)) return {};
              allowed += (allowed.empty() ? "" : ", ") + std::to_string(n);
            }
            if (v == "tones") return {};
            return v + " is out of range: must be one of " + allowed + ", tones";
          },
          "FIGURE"))
      ->required();
  add_common(fig, f.get());
  f->params.add_to(*fig);
  f->params.preset_option->description(
      "Start every cell from this parameter set (parameter flags and --params then change it); the "
      "swept parameters keep the paper's values of their cells");
  fig->add_option("--resolution", f->resolution,
                  "Size of one cell WxH (default 128x128; 160x160 for Fig. 7, 192x192 for Fig. 10 and tones)");
  fig->add_option("--mesh", f->mesh,
                  std::string("The face mesh (OBJ, glTF, GLB; framed by its bounding box as the Lee Perry-Smith "
                              "head) (default: ") + kDefaultHeadMesh + " from the current directory, spheres if absent)");
  fig->add_flag("--spheres", f->spheres, "Render spheres (and a thin fin for the ear) instead of the face");
  fig->callback([f, fig] {
    check_output(f->output);
    if (!f->resolution.empty()) {
      render::RenderSettings tmp;
      parse_resolution(f->resolution, &tmp);
    }
    if (f->spheres && !f->mesh.empty()) throw InputError("--spheres and --mesh exclude each other");
    std::function<SkinParameters(const SkinParameters&)> change;
    if (f->params.given()) change = f->params.change();
    std::string mesh = f->mesh;
    if (mesh.empty() && !f->spheres) {
      std::error_code ec;
      if (std::filesystem::is_regular_file(kDefaultHeadMesh, ec)) {
        mesh = kDefaultHeadMesh;
      } else {
        std::fprintf(stderr, "skin: note: no head mesh at %s: rendering spheres (--mesh PATH names one)\n",
                     kDefaultHeadMesh);
      }
    }
    // Fig. 10's faces and the tone figure's wear the colour texture beside the mesh, when there is one.
    std::string texture;
    if (!mesh.empty()) {
      const std::filesystem::path t = std::filesystem::path(mesh).parent_path() / kHeadTexture;
      std::error_code ec;
      if (std::filesystem::is_regular_file(t, ec)) texture = t.string();
    }
    f->figure = f->figure_name == "tones" ? render::kTonesFigure : std::stoi(f->figure_name);
    render::FigureDescription description = render::describe_figure(f->figure, mesh, texture, change);
    for (auto& cell : description.cells) {
      if (fig->count("--solver") > 0) cell.set_solver(f->solver.model());
      if (f->spectral) cell.set_spectral(true);
    }
    const render::BuildWork work = description.build_work();
    note_profile_solves(work.solved, work.profiles, "profiles (wavelengths and channels of the materials)");
    auto figure = std::make_shared<render::Figure>(
        description.build(work.solved > 0 ? progress_bar("profiles") : util::ProgressCallback{}));
    Target t;
    for (const auto& cell : figure->cells) t.scenes.push_back(&cell);
    t.layout = &figure->layout;
    t.render = [figure](const render::RenderSettings& rs, render::RenderStats* st, const render::Progress& p) {
      return render::render_figure(*figure, rs, st, p);
    };
    run(*f, t);
  });
}

SKIN_REGISTER_COMMAND(70, register_render);

}  // namespace skin::cli
