#pragma once
// Export: this skin in other renderers and engines. For each target, the parameters that make the
// target's own subsurface model reproduce our skin as closely as that model allows, fitted through
// the target's model as the target implements it (its albedo inversion, its profile shape, its
// unit of radius), with the fit's error. The formulas and their sources: docs/export.md.
//
// What is matched, per linear sRGB channel:
// - the diffuse colour under uniform white light: the target's albedo parameter is inverted
//   through the target's own mapping so that its total diffuse reflectance equals our R_d;
// - the mean exit radius of the reflected light, m = int r R(r) dA / int R(r) dA: the width of
//   the light bleeding past a shadow edge is m / pi (the bleed integrates to R_d m / pi).
// The shape of R(r) within a target's family is then what it is; its error is reported.
//
// Units: inputs and the report in mm; files in the unit asked for (Options::unit).
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "skin/image/image.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/model.hpp"
#include "skin/util/progress.hpp"
#include "skin/util/rgb.hpp"

namespace skin::exporting {

enum class Unit { mm, cm, m };
std::string_view unit_name(Unit u);          // "mm", "cm", "m"
std::string_view unit_long_name(Unit u);     // "millimeter", ... (MaterialX distance units)
// Parses "mm", "cm" or "m"; InputError naming `what` otherwise.
Unit parse_unit(std::string_view text, std::string_view what = "units");
double per_mm(Unit u);  // length in u of one mm (1, 0.1, 0.001)

struct Target {
  std::string_view name;         // --target
  std::string_view description;  // one line
  std::string_view extension;    // of the main file, with the dot
  Unit default_unit;             // the target's usual scene unit
  bool takes_textures;           // accepts --parameter-maps
};
const std::vector<Target>& targets();
// The main file's stem when the user names none: NAME.TARGET (e.g. "spectral_skin.cycles"; the
// main file adds the target's extension, the other files their suffixes), as --target all names
// them in its folder. The dot keeps a Python file from shadowing a module: spectral_skin.py
// beside a script would be imported as the package spectral_skin, NAME.TARGET.py cannot be.
std::string default_stem(const Target& target, std::string_view name);
// InputError listing the targets' names otherwise.
const Target& find_target(std::string_view name);
std::string target_names_text();  // "openpbr, standard-surface, ..."
// InputError unless the target takes per-texel textures (--parameter-maps).
void require_textures(const Target& target);

struct Options {
  std::optional<Unit> unit;   // default: the target's
  double world_scale = 1.0;   // scene units per `unit` (> 0): lengths written are x world_scale
  // Material or asset name: [A-Za-z_][A-Za-z0-9_]*, at most 64 (it names classes and nodes, which
  // cannot be escaped; where it is written in a string it is escaped all the same).
  std::string name = "spectral_skin";
  int gaussians = 5;          // realtime: Gaussians in the sum, [2, 8]
  int taps = 17;              // realtime: taps of the separable kernel, odd, [3, 63]
  bool spectra_files = false; // pbrt-v4: sigma_a / sigma_s as .spd files instead of inline
  // File name stem the files use to refer to each other (textures, .spd files, the main file):
  // the main file's name without its extension (the user's -o). Default: name. Any text: each
  // writer escapes it for its format, or refuses it (InputError naming "output") where the format
  // cannot hold it (skin/util/escape.hpp).
  std::string stem;
  void validate() const;      // InputError naming the option
};

// A file of the export, named by the application: `suffix` "" is the main file (the -o path);
// otherwise the main file's stem + suffix (e.g. ".two-layer.pbrt").
// `referenced`: the main file names this file (stem + suffix), so that the main file is of no use
// without it beside it (textures, pbrt-v4's .spd files).
struct TextFile {
  std::string suffix;
  std::string content;
  bool referenced = false;
};
struct ImageFile {
  std::string suffix;   // ".exr" (float planes) or ".png" (8-bit sRGB-encoded colour)
  image::Planes planes; // for .exr
  image::Image rgb;     // for .png (linear values; encoded when written)
  bool referenced = false;
};

// How close the target comes to our skin, per linear sRGB channel. "Ours" is the skin model with
// the chosen transport model; "target" is the target's model with the exported parameters.
struct FitReport {
  std::string target;
  std::string target_model;      // the target's model, in one line
  Unit unit = Unit::mm;
  bool representable = true;     // false where the target's model cannot reach our skin
  std::vector<std::string> notes;
  util::Rgb R_d_ours, R_d_target;      // diffuse reflectance (colour) under uniform white light
  double delta_e_2000 = 0;       // between the two colours (D65, CIEDE2000)
  std::array<double, 3> profile_l1{};         // int |2 pi r (R_t - R_o)| dr / int 2 pi r R_o dr
  std::array<double, 3> mean_radius_mm{};     // ours
  std::array<double, 3> mean_radius_error{};  // (target - ours) / ours
  // The target's parameters as written (name, values), for the report.
  std::vector<std::pair<std::string, std::vector<double>>> values;
  // With parameter maps: how many distinct texels were fitted and the worst colour error.
  std::size_t texels = 0;
  double max_delta_e_2000 = 0;
};

struct Export {
  std::vector<TextFile> files;   // files[0] is the main file (suffix "")
  std::vector<ImageFile> images;
  FitReport report;
};

// Per-texel parameter maps (the channels `skin fit --texture` writes): the named parameters vary
// per texel, everything else is `base`.
struct ParameterMapsInput {
  std::string path;                       // for messages and texture names
  int width = 0, height = 0;
  std::vector<std::string> keys;          // parameter keys, one per plane
  std::vector<std::vector<float>> values; // one plane per key, width * height
};

// Our skin as every target starts from it (its RGB profile, colour and mean exit radii),
// computed once by prepare() and shared by the exports of several targets (--target all).
struct Prepared;
// progress(wavelengths done, wavelengths) while its profile is computed; prepare_solves() is
// how many of those wavelengths the model solves numerically (off the accurate model's skin
// table, or sfd; their cost: docs/benchmarks.md), known before it starts.
std::shared_ptr<const Prepared> prepare(const physics::SkinParameters& parameters,
                                        const transport::Model& model,
                                        const util::ProgressCallback& progress = {});
std::size_t prepare_solves(const physics::SkinParameters& parameters, const transport::Model& model);
std::size_t prepare_wavelengths();
Export export_prepared(std::string_view target, const Prepared& ours, const Options& options);

// Exports `parameters` (validated) for `target` (find_target). progress(texels done, texels) with
// parameter maps, else (wavelengths done, prepare_wavelengths()) while its profile is computed.
Export export_skin(std::string_view target, const physics::SkinParameters& parameters,
                   const transport::Model& model, const Options& options,
                   const ParameterMapsInput* maps = nullptr, const util::ProgressCallback& progress = {});

// The fit report's numbers as the files write them (6 significant digits), and its errors
// (colour differences, relative errors: rounded to 1e-6 absolutely, their noise around zero has
// no significant digits). The report's document (FILE.fit.json, Python's export()["report"]) is
// built by the application's schema (src/schema/export_schema.hpp) with these.
double report_number(double v);
double report_error(double v);

// The target models, exposed for tests and docs (mm, per channel):
// Christensen & Burley 2015 normalized diffusion, R(r) = (e^{-r/d} + e^{-r/3d}) / (8 pi d r),
// integrating to 1; its mean exit radius is 2.5 d.
double burley_profile(double d, double r);
// Chiang, Kutz & Burley 2016 (eq. 3): single-scattering albedo from the multiple-scattering
// albedo A of the random walk (OpenPBR, MaterialX standard_surface, Arnold).
double chiang_alpha(double A);
// Cycles' remap (Blender 3.x/4.x, intern/cycles/kernel/integrator/subsurface_random_walk.h,
// after Wrenninge, Villemin & Hery 2017) at anisotropy g.
double cycles_alpha(double A, double g);

}  // namespace skin::exporting
