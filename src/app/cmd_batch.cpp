// skin batch: the skin model for many parameter sets in one process (skin::batch, all cores),
// one CSV row per set, written as the sets are computed. The sets come from a CSV file (one
// column per parameter key) or from a grid of sweeps; --rows computes a slice, and the slices of
// a table concatenate to the same bytes as one run (the header belongs to the slice starting at
// set 0).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>

#include "batch_schema.hpp"
#include "common.hpp"
#include "progress.hpp"
#include "skin/batch/batch.hpp"
#include "skin/batch/sets.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"
#include "skin/util/table.hpp"

namespace skin::cli {

using skin::util::InputError;
using skin::util::ProgressCallback;
using skin::util::Table;
using skin::util::format_number;
using skin::util::read_csv_file;
using skin::util::require_non_negative;

using skin::transport::RadialGrid;

using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

namespace {

std::string grid_text(const WavelengthGrid& grid) {
  std::ostringstream os;
  os << grid;
  return os.str();
}

}  // namespace

void register_batch(CLI::App& app) {
  struct Opts {
    ParameterOptions params;
    GridOptions grid;
    SolverOption solver;
    std::string sets_file, rows, output;
    std::vector<std::string> sweeps;
    std::vector<double> wavelengths, radii;
    bool spectrum = false;
    int threads = 0;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "batch",
      "The skin model for many parameter sets in one process, on all cores: one CSV row per set "
      "(its colour, R_d at chosen wavelengths, optionally the whole spectrum and the RGB "
      "profile at chosen radii), written as the sets are computed");
  const char* g = "Sets";
  auto* o_sets = sub->add_option("--sets", o->sets_file,
                                 "CSV of parameter sets: one column per parameter key (any subset; "
                                 "symbols accepted), one row per set; an empty cell keeps the base "
                                 "value (--preset, --params, flags)")
                     ->group(g);
  auto* o_sweep = sub->add_option("--sweep", o->sweeps,
                                  "KEY=START:STOP:COUNT: COUNT values from START to STOP; repeat "
                                  "for a grid (the first sweep varies slowest)")
                      ->group(g)->allow_extra_args(false);
  o_sets->excludes(o_sweep);
  sub->add_option("--rows", o->rows,
                  "FIRST:END: compute sets FIRST to END - 1 only (numbered from 0; past the end "
                  "is empty). Slices concatenate to the whole output: the header is written by "
                  "the slice that starts at 0")
      ->group(g);
  o->params.add_to(*sub);
  o->grid.add_to(*sub);
  o->solver.add_to(*sub);
  const char* c = "Columns";
  sub->add_option("--wavelength", o->wavelengths,
                  "R_d at this wavelength [nm] of the grid (repeatable): column R_d_<nm>nm")
      ->group(c)->allow_extra_args(false);
  sub->add_flag("--spectrum", o->spectrum, "R_d at every wavelength of the grid")->group(c);
  sub->add_option("--radius", o->radii,
                  "RGB profile R(r) [1/mm^2] at this radius [mm] (repeatable): columns "
                  "R_<mm>mm.r/g/b (the channel totals are srgb_linear.r/g/b)")
      ->group(c)->allow_extra_args(false);
  sub->add_option("--threads", o->threads, "Worker threads (0 = all cores)")
      ->check(whole_number(0, 4096))->capture_default_str()->group("Run");
  sub->add_option("-o,--output", o->output,
                  "Write the CSV to FILE (atomically, when complete) instead of standard output")
      ->group("Output");
  sub->callback([o] {
    // Everything that can fail on input is checked before the first row is written.
    const SkinParameters base = o->params.resolve();
    auto refuse_flag_too = [&](const ParameterInfo* info, const std::string& by) {
      for (const auto& [opt, flag_info] : o->params.flags)
        if (flag_info == info && opt->count() > 0)
          throw InputError(std::string(info->key) + " is given by both " + opt->get_name() + " and " + by);
    };
    std::vector<batch::Sweep> sweeps;
    std::optional<Table> table;
    batch::Sets sets;
    if (!o->sets_file.empty()) {
      table = read_csv_file(o->sets_file);
      sets = batch::sets_from_table(*table, base);
    } else if (!o->sweeps.empty()) {
      for (const std::string& spec : o->sweeps) sweeps.push_back(batch::parse_sweep(spec));
      sets = batch::sets_from_sweeps(sweeps, base);
    } else {
      throw InputError("batch: give the parameter sets with --sets FILE.csv or --sweep KEY=START:STOP:COUNT");
    }
    for (const ParameterInfo* info : sets.keys) refuse_flag_too(info, sets.source);
    // (plain variables, not a structured binding: the lambdas below capture them, which clang 14,
    // the sanitizer build's compiler, does not allow for bindings)
    const std::pair<std::size_t, std::size_t> range =
        o->rows.empty() ? std::pair<std::size_t, std::size_t>{0, sets.count} : batch::parse_rows(o->rows, sets.count);
    const std::size_t first = range.first, end = range.second;
    sets.validate(first, end);
    if (const std::string ext = util::io::extension(o->output); !o->output.empty() && o->output != "-" &&
                                                           ext != "csv" && ext != "txt" && !ext.empty())
      throw InputError("output = '" + o->output + "': skin batch writes CSV (.csv or .txt)");
    const WavelengthGrid grid = o->grid.resolve();
    const transport::Model& model = o->solver.model();
    schema::BatchLayout layout{sets.keys, grid, {}, o->radii, {}};  // the columns
    for (double w : o->wavelengths) {
      const double x = (w - grid.lambda_min()) / grid.step();
      if (!(x >= -1e-9 && x <= double(grid.size() - 1) + 1e-9) || std::abs(x - std::round(x)) > 1e-9)
        throw InputError("wavelength = " + format_number(w) + " nm is not on the grid (" + grid_text(grid) + ")");
      layout.wavelengths.push_back(static_cast<std::size_t>(std::lround(x)));
    }
    if (o->spectrum)
      for (std::size_t i = 0; i < grid.size(); ++i) layout.wavelengths.push_back(i);
    std::optional<RadialGrid> radii;
    if (!o->radii.empty()) {
      for (double r : o->radii) require_non_negative("radius", r, "mm");
      std::vector<double> sorted = o->radii;
      std::sort(sorted.begin(), sorted.end());
      sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
      for (double r : o->radii)
        layout.radius_index.push_back(static_cast<std::size_t>(std::lower_bound(sorted.begin(), sorted.end(), r) - sorted.begin()));
      radii = RadialGrid::from(sorted);
    }

    // One chunk of sets at a time: computed on all cores, then written, so rows stream out and
    // memory stays bounded for any number of sets.
    const batch::Options run{o->threads, {}};
    const std::size_t chunk = 256;
    // With profiles, wavelengths the model solves rather than reads (about a second each): said
    // before the work starts (batch::profile_solves), and the bar counts wavelengths, not chunks
    // of sets.
    const std::size_t rows = end - first;
    std::size_t solves = 0;
    if (radii) {
      solves = static_cast<std::size_t>(std::llround(
          batch::profile_solves(rows, [&](std::size_t i) { return sets.at(first + i); }, grid, model)));
      note_profile_solves(solves, rows * grid.size(), "wavelength profiles");
    }
    // empty unless stderr is a terminal
    const ProgressCallback progress = progress_bar(solves > 0 ? "wavelengths" : "sets");
    std::size_t wavelengths_done = 0;
    std::mutex bar_mutex;
    // `put` writes the text of a chunk (and throws when it cannot).
    auto write_all = [&](const std::function<void(const std::string&)>& put) {
      for (std::size_t a = first; a < end; a += chunk) {
        const std::size_t b = std::min(end, a + chunk);
        std::vector<SkinParameters> chunk_sets;
        for (std::size_t i = a; i < b; ++i) chunk_sets.push_back(sets.at(i));
        const auto spectra = batch::spectra(chunk_sets, grid, model, run);
        std::vector<batch::RgbProfileResult> profiles;
        if (radii) {
          batch::Options counted = run;
          if (progress && solves > 0)  // from the workers, one at a time so that the count only grows
            counted.progress = [&](std::size_t, std::size_t) {
              const std::lock_guard lock(bar_mutex);
              progress(++wavelengths_done, rows * grid.size());
            };
          profiles = batch::rgb_profiles(chunk_sets, grid, *radii, model, counted);
        }
        const std::vector<Column> columns = schema::batch_columns(layout, a, chunk_sets, spectra, profiles);
        put(a == 0 ? csv_header(columns) + csv_rows(columns) : csv_rows(columns));
        if (progress && solves == 0) progress(b - first, rows);
      }
    };
    if (o->output.empty() || o->output == "-") {
      write_all([](const std::string& text) { util::io::write_stdout(text); });
    } else {
      util::io::write_via_temporary(o->output, [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        if (!f) throw InputError(o->output + ": cannot open for writing");
        write_all([&](const std::string& text) {
          f << text << std::flush;
          if (!f) throw InputError(o->output + ": write failed");
        });
        f.close();
        if (!f) throw InputError(o->output + ": write failed");
      });
    }
  });
}

SKIN_REGISTER_COMMAND(45, register_batch);

}  // namespace skin::cli
