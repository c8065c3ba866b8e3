#pragma once
// Scenes and the Monte Carlo renderer of skin (DJ06 section 5: a path tracer that samples the
// spectral diffusion profiles converted to RGB). The scene format is documented in
// docs/scene-format.md, the integrator in docs/renderer.md. No Embree or TBB type appears here.
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "skin/model/skin_model.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/render/image.hpp"
#include "skin/transport/model.hpp"
#include "skin/util/progress.hpp"

namespace skin::render {

struct RenderSettings {
  int spp = 0;                // samples per pixel; 0 = the scene's
  std::uint64_t seed = 1;     // same seed -> same image, whatever the thread count
  int threads = 0;            // 0 = all hardware threads
  int max_depth = -1;         // path vertices after the camera; -1 = the scene's
  double time_budget = 0;     // seconds; > 0 stops after the last whole sample pass in budget
  int width = 0, height = 0;  // override of the camera resolution (0 = the scene's)
  // Adaptive sampling: > 0 samples in passes (16 per pixel, then doubling) and stops a pixel once
  // its estimated standard error is at most target_error x the mean of the skin pixels, and the
  // render once every pixel has stopped (or at spp, then the most a pixel takes; 0 = 65536).
  double target_error = 0;
  // The subsurface term: probe rays from each exit point (docs/renderer.md), or a point cloud
  // over the translucent meshes with the irradiance entering at each point, summed through an
  // octree (Jensen & Buhler 2002). `scene`: the scene's `subsurface` key (default probes).
  enum class Subsurface { scene, probes, points };
  Subsurface subsurface = Subsurface::scene;
  double point_spacing = 0;       // [mm] sqrt(area per point) of the cloud; 0 = the scene's
  double point_solid_angle = -1;  // [sr] largest A_node / d^2 a tree node stands in for its
                                  // points at; < 0 = the scene's (0 = every point summed)
};

struct RenderStats {
  double seconds = 0;
  int spp_done = 0;                  // samples per pixel actually taken
  std::uint64_t camera_samples = 0;  // pixels x spp_done
  std::uint64_t invalid_samples = 0; // non-finite path contributions dropped (should be 0)
  // Skin pixels: those whose camera samples mostly see a translucent (skin, layered) material;
  // skin_mask has one entry per pixel, row-major, 1 for a skin pixel.
  std::vector<std::uint8_t> skin_mask;
  std::size_t skin_pixels = 0;
  // The relative RMS error of the image over the skin pixels estimated from the samples' own
  // spread: sqrt(mean over skin pixels and channels of the variance of the pixel's mean) / the
  // mean over skin pixels and channels (NaN when fewer than 2 samples per pixel or no skin).
  double estimated_error = 0;
  // Subsurface from points: the cloud's size and the wall time of building it (distribution,
  // irradiance, octree, exitance cache), included in `seconds` and in a --time-budget.
  std::size_t points = 0;
  double point_seconds = 0;
  double point_spacing = 0;  // [mm]
  double samples_per_second() const { return seconds > 0 ? static_cast<double>(camera_samples) / seconds : 0; }
};

std::ostream& operator<<(std::ostream& os, const RenderSettings& s);
std::ostream& operator<<(std::ostream& os, const RenderStats& s);

class Scene;

// The profiles a build computes: `profiles` in all (a skin's wavelengths, a layered material's
// three channels; each distinct one once), of which `solved` are solved numerically by their
// transport model (transport::Model::response_is_solved: off the accurate model's skin table, or
// sfd) rather than read from a table (their cost: docs/benchmarks.md).
struct BuildWork {
  std::size_t profiles = 0;
  std::size_t solved = 0;
};

// A scene as described, before any physics: what the scene file (or the built-in scene) says,
// edited by the CLI's flags and by `skin figure`; build() then computes every material once.
// Its materials are skin (parameters, parameter maps, an albedo texture and its reference),
// layered (a layer stack per channel) or diffuse, each translucent one with its solver.
class SceneDescription {
 public:
  // Reads a JSON scene; relative paths in it are relative to the file. Throws InputError naming
  // the file and the problem (missing mesh or texture, malformed JSON, unknown key or material,
  // a parameter out of range).
  static SceneDescription load(const std::string& path);
  // Parses JSON text; `base_dir` resolves relative paths, `name` appears in messages.
  static SceneDescription parse(const std::string& json_text, const std::string& base_dir, const std::string& name);
  // The built-in scene: the three Fig. 8 skin types on rounded shapes and a thin ear-like fin,
  // key light in front, back light behind the fin. Needs no file.
  static SceneDescription default_scene();

  // Edits (no physics runs until build()).
  // Replaces the parameters of every `skin` material (the CLI's --preset).
  void set_skin_parameters(const physics::SkinParameters& p);
  // Changes the parameters of every `skin` material: each gets change(its parameters) (the CLI's
  // parameter flags, applied to each material's own set). Mapped parameters keep their maps.
  void update_skin_parameters(const std::function<physics::SkinParameters(const physics::SkinParameters&)>& change);
  // Every translucent material (skin, layered) with this transport model (the CLI's --solver; a
  // material's own `solver` key otherwise, the registry's default without one).
  void set_solver(const transport::Model& solver);
  // Spectral rendering (hero wavelength, spectral profiles and lights; docs/renderer.md) instead
  // of RGB (the paper's method, the default); the scene key render.spectral. InputError when
  // turning it on with a layered material (its stacks are RGB).
  void set_spectral(bool spectral);
  bool spectral() const;
  // Every translucent material rendered as a `diffuse` one of the same R_d (for benchmarks).
  void make_translucent_diffuse();

  // Computes the materials' profiles (each distinct skin once) and the acceleration structure.
  // InputError names the scene and the material. With `progress`, the materials that solve
  // profiles (build_work) report per wavelength.
  Scene build(const util::ProgressCallback& progress = {}) const;
  // What build() will compute, known before it starts (to announce a long build).
  BuildWork build_work() const;

  SceneDescription(const SceneDescription&);
  SceneDescription& operator=(const SceneDescription&);
  SceneDescription(SceneDescription&&) noexcept;
  SceneDescription& operator=(SceneDescription&&) noexcept;
  ~SceneDescription();

  struct Data;
  const Data& data() const { return *d_; }
  Data& data() { return *d_; }
  explicit SceneDescription(std::unique_ptr<Data> d);

 private:
  std::unique_ptr<Data> d_;
};

// Builds several descriptions together (a figure's cells): each distinct skin over all of them
// is computed once.
std::vector<Scene> build(const std::vector<const SceneDescription*>& descriptions,
                         const util::ProgressCallback& progress = {});
BuildWork build_work(const std::vector<const SceneDescription*>& descriptions);

// A built scene: what render() takes.
class Scene {
 public:
  // SceneDescription::load(path).build(), and the same for parse and default_scene.
  static Scene load(const std::string& path);
  static Scene parse(const std::string& json_text, const std::string& base_dir, const std::string& name);
  static Scene default_scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;
  ~Scene();

  // The translucent materials whose profiles are outside their model's validated range.
  struct MaterialValidity {
    std::string material, solver;
    transport::Validity validity;
  };
  std::vector<MaterialValidity> validity() const;
  bool spectral() const;
  int width() const;
  int height() const;
  double exposure() const;  // stops, for PNG output
  ToneMap tone_map() const;  // the tone curve of PNG output (the scene key render.tone_map)
  std::string summary() const;  // one line: source, triangles, materials, lights

  struct Impl;
  const Impl& impl() const { return *impl_; }
  explicit Scene(std::unique_ptr<Impl> impl);

 private:
  std::unique_ptr<Impl> impl_;
};

// Progress in [0, 1]; may be called from any render thread (calls are serialised).
using Progress = std::function<void(double fraction)>;

Image render(const Scene& scene, const RenderSettings& settings, RenderStats* stats = nullptr,
             const Progress& progress = {});

// The relative RMS error of `image` against `reference` over the pixels where mask is 1:
// sqrt(mean of (image - reference)^2 over those pixels and the three channels) / the mean of the
// reference there (the measure estimated_error estimates). InputError when the sizes differ or
// the mask is empty.
double relative_rms_error(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask);

// What render() would take with these settings, to check a request before it starts.
struct RenderCost {
  double samples = 0;  // camera samples: pixels x spp (before any time budget)
  double bytes = 0;    // memory of the image sums
};
RenderCost render_cost(const Scene& scene, const RenderSettings& settings);

}  // namespace skin::render
