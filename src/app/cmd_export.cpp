// skin export: this skin's parameters for other renderers and engines, each fitted through the
// target's own model, with the fit's error beside the files (docs/export.md).
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "common.hpp"
#include "export_schema.hpp"
#include "progress.hpp"
#include "skin/export/export.hpp"
#include "skin/image/image.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"

namespace skin::cli {

using skin::util::InputError;

using skin::physics::SkinParameters;

namespace {

// "dir/name.ext" -> "dir/name"
std::string stem_of(const std::string& path) {
  std::filesystem::path p(path);
  return p.has_extension() ? p.replace_extension().string() : path;
}

// Whether `path` is written in place rather than as a file (io::write_file_atomic): standard
// output ("-"), or an existing FIFO or device (behind any symbolic links: /dev/stdout).
bool written_in_place(const std::string& path) {
  if (path == "-") return true;
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  return !ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) &&
         !std::filesystem::is_directory(st);
}

std::string percent(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.1f%%", 100.0 * v);
  return buf;
}

}  // namespace

void register_export(CLI::App& app) {
  struct Opts {
    ParameterOptions params;
    SolverOption solver;
    std::string target;
    std::string units;
    double world_scale = 1.0;
    std::string name = "spectral_skin";
    std::string output;
    std::string maps;
    int gaussians = 5, taps = 17;
    bool spectra_files = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "export",
      "Export this skin to another renderer or engine: the target's parameters fitted through its "
      "own subsurface model, with the fit's error in FILE.fit.json (docs/export.md)");
  o->params.add_to(*sub);
  o->solver.add_to(*sub);
  sub->add_option("--target", o->target,
                  "Target: " + exporting::target_names_text() + ", or all (-o names a folder)")
      ->required();
  sub->add_option("--units", o->units,
                  "Length unit of the files: mm, cm or m (default: the target's usual one)");
  sub->add_option("--world-scale", o->world_scale,
                  "Scene units per --units unit (lengths written are multiplied by it), > 0")
      ->capture_default_str();
  sub->add_option("--name", o->name, "Material or asset name")->capture_default_str();
  sub->add_option("-o,--output", o->output,
                  "Main file (default NAME.TARGET + the target's extension; beside it FILE.fit.json "
                  "and any other files); with --target all, a folder. A FIFO, a device or - "
                  "(standard output) takes the main file alone")
      ->group("Output");
  sub->add_option("--parameter-maps", o->maps,
                  "Per-texel parameters (the EXR `skin fit --texture` writes): per-texel colour and "
                  "radius textures, for the targets that take textures");
  sub->add_option("--gaussians", o->gaussians, "realtime: Gaussians in the sum, [2, 8]")
      ->capture_default_str();
  sub->add_option("--taps", o->taps, "realtime: taps of the separable kernel, odd, [3, 63]")
      ->capture_default_str();
  sub->add_flag("--spectra-files", o->spectra_files,
                "pbrt-v4: write sigma_a and sigma_s as .spd files instead of inline");
  sub->callback([o] {
    const SkinParameters p = o->params.resolve();
    const transport::Model& model = o->solver.model();
    exporting::Options opt;
    if (!o->units.empty()) opt.unit = exporting::parse_unit(o->units);
    opt.world_scale = o->world_scale;
    opt.name = o->name;
    opt.gaussians = o->gaussians;
    opt.taps = o->taps;
    opt.spectra_files = o->spectra_files;
    opt.validate();
    std::vector<const exporting::Target*> chosen;
    const bool all = o->target == "all";
    if (all) {
      if (!o->maps.empty())
        throw InputError("parameter-maps: not with --target all (give one target that takes textures)");
      for (const exporting::Target& t : exporting::targets()) chosen.push_back(&t);
    } else {
      chosen.push_back(&exporting::find_target(o->target));
    }
    std::optional<exporting::ParameterMapsInput> maps;
    if (!o->maps.empty()) {
      exporting::require_textures(*chosen[0]);
      // The three maps of every fit and, from --model extended, the maps of its other free
      // parameters (each named by its key): all of them vary per texel.
      std::vector<std::string> keys = {"melanin", "melanin_blend", "hemoglobin"};
      for (const std::string& k : physics::parameter_channels(image::exr_channel_names(o->maps, "parameter maps")))
        if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
      image::Planes planes = image::read_exr_planes(o->maps, keys, "parameter maps");
      maps = exporting::ParameterMapsInput{o->maps, planes.width, planes.height, keys,
                                           std::move(planes.values)};
    }
    // Our profile and colour, shared by the targets.
    // Off the skin table each wavelength is solved: said before it starts, with an estimate, and
    // a bar on a terminal.
    const std::size_t solves = maps ? 0 : exporting::prepare_solves(p, model);
    note_profile_solves(solves, exporting::prepare_wavelengths());
    const std::shared_ptr<const exporting::Prepared> ours =
        maps ? nullptr : exporting::prepare(p, model, solves > 0 ? progress_bar("wavelengths") : util::ProgressCallback{});
    std::string folder;
    if (all) {
      folder = o->output.empty() ? "." : o->output;
      std::error_code ec;
      if (!std::filesystem::is_directory(folder, ec))
        throw InputError(folder + ": not a folder (with --target all, -o names an existing folder)");
    }
    // Every target's files and report are made, and every name checked, before the first file is
    // written: a refusal (a file name a format cannot hold, a pipe for a main file that needs
    // files beside it) leaves nothing half-written.
    struct Job {
      exporting::Export e;
      std::string main_path, stem, report;
      bool in_place = false;  // the main file goes to a pipe, a device or standard output
      std::vector<std::string> written, skipped;
    };
    std::vector<Job> jobs;
    for (const exporting::Target* t : chosen) {
      Job j;
      const std::string main_name =
          exporting::default_stem(*t, o->name) + std::string(t->extension);
      j.main_path = all ? (std::filesystem::path(folder) / main_name).string()
                    : o->output.empty() ? main_name
                                        : o->output;
      j.stem = stem_of(j.main_path);
      j.in_place = !all && written_in_place(j.main_path);
      opt.stem = std::filesystem::path(j.stem).filename().string();
      j.e = maps ? exporting::export_skin(t->name, p, model, opt, &*maps, progress_bar("texels"))
                 : exporting::export_prepared(t->name, *ours, opt);
      // Written in place, the main file goes alone: no side file is created beside a pipe or a
      // device (/dev/null.fit.json). A main file that names its side files is refused there.
      auto side = [&](const std::string& suffix, bool referenced) {
        const std::string path = j.stem + suffix;
        if (!j.in_place) return j.written.push_back(path);
        if (referenced)
          throw InputError("output = '" + j.main_path + "' is not a regular file (a pipe, a device "
                           "or standard output), where the " + std::string(t->name) +
                           " export's main file names " + path +
                           " beside it: give a file name");
        j.skipped.push_back(path);
      };
      for (const exporting::TextFile& f : j.e.files) {
        if (f.suffix.empty()) j.written.push_back(j.main_path);
        else side(f.suffix, f.referenced);
      }
      for (const exporting::ImageFile& f : j.e.images) side(f.suffix, f.referenced);
      side(".fit.json", false);
      if (!j.in_place) j.report = schema::fit_report_document(j.e.report, p, o->solver.name, j.written).dump(2) + "\n";
      jobs.push_back(std::move(j));
    }
    for (const Job& j : jobs) {
      const exporting::Export& e = j.e;
      for (const exporting::TextFile& f : e.files)
        if (f.suffix.empty() || !j.in_place)
          util::io::write_file_atomic(f.suffix.empty() ? j.main_path : j.stem + f.suffix, f.content);
      for (const exporting::ImageFile& f : e.images) {
        if (j.in_place) continue;
        const std::string path = j.stem + f.suffix;
        if (util::io::extension(path) == "exr")
          image::write_exr_planes(path, f.planes, {{"skin_export", e.report.target}},
                                  "export " + e.report.target);
        else
          image::write_image(path, f.rgb);
      }
      if (!j.in_place) util::io::write_file_atomic(j.stem + ".fit.json", j.report);
      // Beside data written to standard output or a pipe the summary goes to standard error.
      std::ostream& out = j.in_place ? std::cerr : std::cout;
      const auto& r = e.report;
      out << r.target << ": wrote";
      for (const std::string& w : j.written) out << ' ' << w;
      if (!j.skipped.empty()) {
        out << " (alone: not a regular file; not written:";
        for (const std::string& w : j.skipped) out << ' ' << w;
        out << ")";
      }
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "\n  colour dE2000 %.2f; profile L1 r/g/b %.2f/%.2f/%.2f; mean radius %.3g/%.3g/%.3g mm",
                    r.delta_e_2000, r.profile_l1[0], r.profile_l1[1], r.profile_l1[2],
                    r.mean_radius_mm[0], r.mean_radius_mm[1], r.mean_radius_mm[2]);
      out << buf << " (target " << percent(r.mean_radius_error[0]) << "/"
                << percent(r.mean_radius_error[1]) << "/" << percent(r.mean_radius_error[2])
                << ")\n";
      if (!r.representable) std::cerr << "skin: warning: " << r.target << ": " << r.notes.front() << '\n';
    }
  });
}

SKIN_REGISTER_COMMAND(65, register_export);

}  // namespace skin::cli
