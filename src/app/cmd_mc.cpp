// skin mc: Monte Carlo photon transport in a layer stack (the validation reference).
// skin validate: the transport models against Monte Carlo over the presets and generic stacks ->
// report.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "common.hpp"
#include "mc_schema.hpp"
#include "progress.hpp"
#include "report_validation.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/mc/mc.hpp"
#include "skin/mc/tabulate.hpp"
#include "skin/transport/half_space_table.hpp"
#include "skin/transport/skin_stack_table.hpp"
#include "skin/mc/validation.hpp"
#include "skin/util/error.hpp"
#include "skin/util/input_file.hpp"
#include "skin/util/table.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/profile.hpp"
#ifdef SKIN_HAVE_FIT
#include "report_measured.hpp"
#endif

namespace skin::cli {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::require_in_range;

using skin::physics::LayerStack;
using skin::physics::skin_layer_stack;

namespace {

struct McOptions {
  std::uint64_t photons = 100000;
  RunOptions run;
  double r_max = 10.0;
  std::size_t bins = 200;
  void add_to(CLI::App& app, std::uint64_t default_photons, std::size_t default_bins,
              bool with_radius) {
    photons = default_photons;
    bins = default_bins;
    const char* g = "Monte Carlo";
    app.add_option("--photons", photons, "Photon packets entering the medium (per case)")
        ->check(whole_number(1))->capture_default_str()->group(g);
    run.add_to(app, "Seed; the same seed gives identical results for any thread count", g);
    if (with_radius)
      app.add_option("--radius-max", r_max, "Outer radius of the radial profile R(r) [mm], > 0")
          ->capture_default_str()->group(g);
    app.add_option("--bins", bins, "Annular bins of the radial profile")
        ->check(whole_number(1, 1000000))->capture_default_str()->group(g);
  }
  mc::Options resolve() const {
    mc::Options o;
    o.photons = photons;
    o.seed = run.seed;
    o.threads = run.threads;
    o.r_max = r_max;
    o.bins = bins;
    o.progress = progress_bar("photons");  // drawn on a terminal only
    return o;
  }
};

void register_mc_command(CLI::App& app) {
  struct Opts {
    StackOptions stack;
    double wavelength = 0;
    ParameterOptions params;
    McOptions mc;
    OutputOptions out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "mc",
      "Monte Carlo photon transport in a layer stack (MCML method: pencil beam at normal "
      "incidence, Henyey-Greenstein scattering, exact Fresnel at every interface). Either "
      "--layer ... or --wavelength NM with the skin model (--preset and parameter flags). "
      "Reflectances per power that entered the medium; lengths in mm, coefficients in 1/mm");
  CLI::Option* layer_opt = o->stack.add_to(*sub, " (instead of --wavelength)");
  CLI::Option* wl_opt = sub->add_option(
      "--wavelength", o->wavelength,
      "Simulate the two-layer skin model at this wavelength [nm] (instead of --layer)");
  wl_opt->excludes(layer_opt);
  o->params.add_to(*sub);
  o->mc.add_to(*sub, 100000, 200, true);
  o->out.add_to(*sub);
  sub->callback([o, sub, wl_opt] {
    LayerStack stack;
    std::optional<schema::McSkin> skin;  // with --wavelength: the skin the stack is made of
    if (o->stack.given()) {
      // Skin parameters only make sense with --wavelength: reject them with --layer.
      if (o->params.preset_option->count() > 0)
        throw InputError("--preset needs --wavelength and cannot be combined with --layer");
      if (o->params.params_option->count() > 0)
        throw InputError("--params needs --wavelength and cannot be combined with --layer");
      for (const auto& [opt, info] : o->params.flags)
        if (opt->count() > 0)
          throw InputError(opt->get_name() + " needs --wavelength and cannot be combined with --layer");
      stack = o->stack.resolve();
    } else if (wl_opt->count() > 0) {
      require_in_range("wavelength", o->wavelength, 250.0, 1000.0, "nm");
      skin = schema::McSkin{o->params.preset, o->params.resolve(), o->wavelength};
      stack = skin_layer_stack(skin->parameters, o->wavelength);
    } else {
      throw InputError("give either --layer ... or --wavelength NM (with --preset / parameters)");
    }
    stack.validate();
    const mc::Options opts = o->mc.resolve();
    (void)o->out.resolve();  // a contradicting --format fails before the run
    // Measured on this stack (a pilot of ~0.05 s): a clear or thin medium runs at a rate far
    // from skin's.
    warn_if_long(mc::estimate(stack, opts));
    const mc::Result r = mc::simulate(stack, opts);
    o->out.write(schema::mc_result(stack, r, opts.seed, skin));
  });
}

void register_validate_command(CLI::App& app) {
  struct Opts {
    std::string out;
    std::string spectra_dir;
    std::vector<double> wavelengths{450, 550, 650};
    McOptions mc;
    std::size_t domain = 0;
    std::uint64_t domain_seed = 1;
  };
  auto o = std::make_shared<Opts>();
#ifdef SKIN_HAVE_FIT
  o->spectra_dir = default_spectra_dir();
#else
  o->spectra_dir = "../shared/data/skin_spectra";
#endif
  CLI::App* sub = app.add_subcommand(
      "validate",
      "The transport models (multipole, accurate, sfd) against Monte Carlo over the paper's presets at several "
      "wavelengths and over generic layer stacks, and the model against measured skin spectra; "
      "writes OUT/README.md (tables, errors), PNG profiles and OUT/measured/");
  sub->add_option("--out", o->out, "Output directory (created if missing)")->required();
  sub->add_option("--wavelength", o->wavelengths, "Wavelengths of the preset cases [nm] (repeatable)")
      ->capture_default_str()->allow_extra_args(false);
  sub->add_option("--spectra-dir", o->spectra_dir,
                  "Measured skin spectra (CSV) for the measured-spectra part; skipped if absent "
                  "(default: $SKIN_SPECTRA_DIR, else ../shared/data/skin_spectra from the current "
                  "directory)")
      ->capture_default_str();
  o->mc.add_to(*sub, 1000000, 200, false);
  sub->add_option("--domain", o->domain,
                  "Instead of the presets and stacks: this many skin cases drawn from the skin domain "
                  "(skin parameters), each at one wavelength, checked as issue 31 states (annuli of "
                  "0.02 mm unless --bins is given); writes OUT/README.md with maps of the domain")
      ->check(whole_number(1, 100000));
  sub->add_option("--domain-seed", o->domain_seed, "Seed of the --domain draw (the same cases for the same seed)")
      ->capture_default_str();
  sub->callback([sub, o] {
    for (double l : o->wavelengths) require_in_range("wavelength", l, 250.0, 1000.0, "nm");
    mc::Options opts = o->mc.resolve();
    opts.progress = {};  // one line per case instead (below)
    // Check the options before the long run starts (simulate() checks them again per case).
    if (opts.photons < 1) throw InputError("photons = 0 is out of range: must be >= 1");
    // The cases through Monte Carlo and the named models, after the request is checked; one line
    // per finished case on a terminal.
    auto run_cases = [&](const std::vector<mc::ValidationCase>& cases,
                         const std::vector<std::string>& names) {
      check_request("a validation of " + std::to_string(cases.size()) + " cases of " +
                        std::to_string(opts.photons) + " photons",
                    static_cast<double>(cases.size()) * static_cast<double>(opts.photons),
                    kMcPhotonsPerSecond, opts.threads, mc::memory_bytes(opts));
      std::filesystem::create_directories(o->out);
      std::vector<mc::SolverColumn> solvers;
      for (const auto& n : names) solvers.push_back(mc::solver_column(transport::find_model(n)));
      mc::CaseDone log;
      if (stderr_is_terminal())
        log = [&names](std::size_t done, std::size_t total, const mc::CaseResult& c) {
          std::cerr << "[" << done << "/" << total << "] " << validation_case_line(c, names) << '\n';
        };
      return mc::run_validation(cases, solvers, opts, log);
    };
    if (o->domain > 0) {
      if (sub->count("--bins") == 0) opts.bins = 500;  // annuli of 0.02 mm to 10 mm
      const std::vector<mc::ValidationCase> cases = mc::domain_cases(o->domain, o->domain_seed);
      const mc::ValidationRun run = run_cases(cases, {"multipole", "accurate"});
      std::ostringstream md;
      write_domain_report(md, run, o->out, o->domain_seed);
      util::io::write_file_atomic(o->out + "/README.md", md.str());
      std::cout << "wrote " << o->out << "/README.md and 4 maps (" << run.cases.size() << " cases, "
                << format_number(run.seconds) << " s)\n";
      return;
    }
    std::vector<mc::ValidationCase> cases = mc::preset_cases(o->wavelengths);
    for (auto& c : mc::generic_cases()) cases.push_back(std::move(c));
    const mc::ValidationRun run = run_cases(cases, {"multipole", "accurate", "sfd"});
#ifdef SKIN_HAVE_FIT
    // The model fitted to every measured spectrum, with each solver (skin::fit). Everything is
    // computed before the first file is written, so that an interrupted run leaves an earlier
    // report whole.
    const bool measured = std::filesystem::is_directory(o->spectra_dir);
    std::vector<std::pair<std::string, std::vector<fit::MeasuredEntry>>> fits;
    for (const char* solver : {"multipole", "accurate"})
      if (measured) fits.emplace_back(solver, fit::fit_measured_spectra(o->spectra_dir, fit::forward_model(solver)));
#endif
    std::ostringstream md;
    const std::size_t plots = write_validation_report(md, run, o->out, "");
    md << "\n## Measured skin spectra\n\n";
#ifdef SKIN_HAVE_FIT
    if (measured) {
      for (const auto& [solver, entries] : fits) {
        const std::string sub_dir = std::string("measured/") + (solver == "multipole" ? "" : "accurate/");
        write_measured_report(entries, o->spectra_dir, o->out + "/" + sub_dir, solver);
        md << "- with the " << solver << " solver: [" << sub_dir << "README.md](" << sub_dir
           << "README.md)\n";
      }
    } else {
      md << "Skipped: no measured spectra at " << o->spectra_dir << ".\n";
    }
#else
    md << "Not built (the fitting library is needed).\n";
#endif
    util::io::write_file_atomic(o->out + "/README.md", md.str());
    std::cout << "wrote " << o->out << "/README.md and " << plots
              << " plots (" << run.cases.size() << " cases, " << format_number(run.seconds)
              << " s)\n";
  });
}

}  // namespace

void register_random_walk_command(CLI::App& app) {
  struct Opts {
    std::string out;
    mc::RandomWalkOptions t = mc::RandomWalkOptions::defaults();
    RunOptions run;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "tabulate-random-walk",
      "Tabulate a renderer's random-walk subsurface response (index-matched half-space, Lambertian "
      "entry) by Monte Carlo over the single-scattering albedo: the data file "
      "data/random_walk_g0.csv that `skin export` fits renderers' parameters with");
  sub->add_option("-o,--output", o->out, "Output CSV file (written atomically)")->required();
  sub->add_option("--photons", o->t.photons, "Photons per node")
      ->check(whole_number(1))->capture_default_str();
  o->run.seed = o->t.seed;
  o->run.threads = o->t.threads;
  o->run.add_to(*sub, "Seed; the same seed gives the same table for any thread count");
  sub->callback([o] {
    o->t.progress = progress_bar("nodes");  // drawn on a terminal only
    o->t.seed = o->run.seed;
    o->t.threads = o->run.threads;
    const transport::RandomWalkTable table = mc::tabulate_random_walk(o->t);
    util::io::write_file_atomic(o->out, table.to_csv());
    std::cout << "wrote " << o->out << ": " << table << '\n';
  });
}

void register_skin_table_command(CLI::App& app) {
  struct Opts {
    std::string out, reuse, rebase_from;
    bool offsets = false, cross = false, half_spaces = false;
    std::vector<std::string> axes, pairs;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "tabulate-skin-profiles",
      "Tabulate the frequency-domain (sfd) radial profiles of the two-layer skin geometry over its "
      "reduced parameters: the data file data/skin_stack_profiles.csv that the accurate solver "
      "reads for skin (about 34 min on 2 cores; with --reuse only the nodes the given table lacks)");
  sub->add_option("-o,--output", o->out, "Output CSV file (written atomically)")->required();
  sub->add_option("--reuse", o->reuse,
                  "A table of this kind (e.g. data/skin_stack_profiles.csv) whose nodes are copied instead of "
                  "solved: only new nodes are computed");
  sub->add_flag("--offsets", o->offsets,
                "Tabulate instead the offsets of the built-in table for another g, index and dermis ratio "
                "(data/skin_stack_offsets.csv; about 45 min on 2 cores)");
  sub->add_flag("--cross", o->cross,
                "Tabulate instead the cross terms of the built-in offsets, for two of g, index and dermis ratio "
                "off the table's at once (data/skin_stack_cross.csv; on the offsets' nodes, ~15 min per corner on 2 cores, g 0.97 several times more; with --reuse only the corners it lacks, or only the new nodes of the reused corners)")
      ->excludes("--offsets");
  sub->add_flag("--half-spaces", o->half_spaces,
                "Tabulate instead the profiles of absorbing half-spaces over sigma_a / sigma_s', g and index "
                "(data/half_space_profiles.csv: what a top layer that hides the rest is read as; about 50 min on 2 cores)")
      ->excludes("--offsets")
      ->excludes("--cross");
  sub->add_option("--offset-nodes", o->axes,
                  "With --offsets: only these nodes, as AXIS=VALUE (g=0.8, eta=1.47, dermis_ratio=2); default: all");
  sub->add_option("--cross-pairs", o->pairs,
                  "With --cross: solve only these pairs of axes (g:eta, g:dermis_ratio, eta:dermis_ratio); default: all. "
                  "With --reuse, the corners it holds are copied in every case, and the other pairs' corners on a side "
                  "where it had none are its other side's continued through the base (reads as before); others 0");
  sub->add_option("--rebase-from", o->rebase_from,
                  "With --cross --reuse: the offsets file the reused terms were computed against; writes those "
                  "terms rebased onto the built-in offsets (each corner's term changes by the offsets' change "
                  "there), nothing solved");
  sub->callback([o] {
    if (o->half_spaces) {
      namespace acc = transport::accurate;
      if (!o->axes.empty() || !o->pairs.empty() || !o->rebase_from.empty())
        throw util::InputError("--half-spaces takes only --output and --reuse");
      acc::HalfSpaceTable table = acc::HalfSpaceTable::default_nodes();
      table.provenance = "skin tabulate-skin-profiles --half-spaces (FrequencyStack, k0 = 0.02 s)";
      std::optional<acc::HalfSpaceTable> reuse;
      if (!o->reuse.empty()) reuse = acc::HalfSpaceTable::parse(util::io::read_file(o->reuse, "reuse", std::uintmax_t{64} << 20), o->reuse);
      table.compute(progress_bar("half-spaces"), reuse ? &*reuse : nullptr);
      util::io::write_file_atomic(o->out, table.to_csv());
      std::cout << "wrote " << o->out << ": " << table.g.size() * table.eta.size() * table.a.size() << " half-spaces, "
                << table.x.size() << " radii each\n";
      return;
    }
    if (!o->rebase_from.empty() && (!o->cross || o->reuse.empty()))
      throw util::InputError("--rebase-from is for --cross with --reuse (the terms to rebase)");
    if (o->cross) {
      namespace acc = transport::accurate;
      if (!o->axes.empty()) throw util::InputError("--cross does not take --offset-nodes");
      std::array<bool, acc::SkinStackCross::kPairs> pairs{false, false, false};
      if (!o->pairs.empty()) {
        static const char* const kNames[acc::SkinStackCross::kPairs] = {"g:eta", "g:dermis_ratio", "eta:dermis_ratio"};
        for (const std::string& name : o->pairs) {
          const auto* hit = std::find(std::begin(kNames), std::end(kNames), name);
          if (hit == std::end(kNames))
            throw util::InputError("--cross-pairs: '" + name + "' is not one of g:eta, g:dermis_ratio, eta:dermis_ratio");
          pairs[static_cast<std::size_t>(hit - std::begin(kNames))] = true;
        }
      }
      // The built-in table and offsets, without their own cross terms.
      acc::SkinStackTable table = acc::SkinStackTable::parse(util::data::embedded("skin_stack_profiles.csv"), "skin_stack_profiles.csv");
      acc::SkinStackOffsets offsets = acc::SkinStackOffsets::parse(util::data::embedded("skin_stack_offsets.csv"), "skin_stack_offsets.csv");
      offsets.settle(table);
      std::optional<acc::SkinStackOffsets> before;  // the offsets the reused terms were computed against
      if (!o->rebase_from.empty()) {
        before = acc::SkinStackOffsets::parse(util::io::read_file(o->rebase_from, "rebase-from", std::uintmax_t{64} << 20), o->rebase_from);
        before->settle(table);
      }
      table.settle();
      table.offsets = &offsets;
      acc::SkinStackCross cross = acc::SkinStackCross::default_nodes(offsets);
      cross.provenance = "skin tabulate-skin-profiles --cross (FrequencyStack, k0 = 0.02 s)";
      std::optional<acc::SkinStackCross> reuse;
      if (!o->reuse.empty()) reuse = acc::SkinStackCross::parse(util::io::read_file(o->reuse, "reuse", std::uintmax_t{64} << 20), o->reuse);
      // Terms extended to new nodes of the offsets keep their corners.
      if (reuse && (reuse->tau != cross.tau || reuse->a_e != cross.a_e || reuse->a_d != cross.a_d)) cross.ends = reuse->ends;
      if (before) {  // the reused terms rebased, nothing solved
        acc::SkinStackCross rebased = *reuse;
        try {
          rebased.rebase(*before, offsets);
        } catch (const std::logic_error&) {
          throw util::InputError("--rebase-from: " + o->rebase_from + " is not on the nodes of the reused terms and the built-in offsets");
        }
        rebased.provenance += "; rebased onto other offsets (--rebase-from)";
        util::io::write_file_atomic(o->out, rebased.to_csv());
        std::cout << "wrote " << o->out << '\n';
        return;
      }
      cross.compute(table, progress_bar("stacks"), reuse ? &*reuse : nullptr, o->pairs.empty() ? nullptr : &pairs);
      util::io::write_file_atomic(o->out, cross.to_csv());
      std::cout << "wrote " << o->out << '\n';
      return;
    }
    if (!o->pairs.empty()) throw util::InputError("--cross-pairs is for --cross");
    if (o->offsets) {
      namespace acc = transport::accurate;
      const acc::SkinStackTable table = acc::SkinStackTable::parse(util::data::embedded("skin_stack_profiles.csv"), "skin_stack_profiles.csv");
      acc::SkinStackOffsets offsets = acc::SkinStackOffsets::default_nodes(table);
      offsets.provenance = "skin tabulate-skin-profiles --offsets (FrequencyStack, k0 = 0.02 s)";
      if (!o->axes.empty()) {
        std::array<std::vector<double>, acc::SkinStackOffsets::kAxes> only;
        for (int a = 0; a < acc::SkinStackOffsets::kAxes; ++a) only[a] = {offsets.base[a]};
        for (const std::string& spec : o->axes) {
          const auto eq = spec.find('=');
          int axis = -1;
          for (int a = 0; a < acc::SkinStackOffsets::kAxes; ++a)
            if (spec.substr(0, eq) == acc::SkinStackOffsets::kAxisNames[a]) axis = a;
          if (eq == std::string::npos || axis < 0)
            throw util::InputError("--offset-nodes: '" + spec + "' is not AXIS=VALUE with AXIS one of g, eta, dermis_ratio");
          const std::vector<double> v = util::parse_number_list(spec.substr(eq + 1), "--offset-nodes", spec.substr(0, eq));
          only[axis].insert(only[axis].end(), v.begin(), v.end());
        }
        for (auto& v : only) std::sort(v.begin(), v.end());
        offsets.nodes = only;
      }
      std::optional<acc::SkinStackOffsets> reuse;
      if (!o->reuse.empty()) reuse = acc::SkinStackOffsets::parse(util::io::read_file(o->reuse, "reuse", std::uintmax_t{64} << 20), o->reuse);
      offsets.compute(table, progress_bar("stacks"), reuse ? &*reuse : nullptr);
      util::io::write_file_atomic(o->out, offsets.to_csv());
      std::cout << "wrote " << o->out << '\n';
      return;
    }
    transport::accurate::SkinStackTable table = transport::accurate::SkinStackTable::default_nodes();
    table.provenance = "skin tabulate-skin-profiles (FrequencyStack, k0 = 0.02 s)";
    std::optional<transport::accurate::SkinStackTable> reuse;
    if (!o->reuse.empty()) reuse = transport::accurate::SkinStackTable::parse(util::io::read_file(o->reuse, "reuse", std::uintmax_t{64} << 20), o->reuse);
    table.compute(progress_bar("nodes"), reuse ? &*reuse : nullptr);  // drawn on a terminal only
    util::io::write_file_atomic(o->out, table.to_csv());
    std::cout << "wrote " << o->out << ": " << table.tau.size() * table.a_e.size() * table.a_d.size()
              << " stacks, " << table.x.size() << " radii each\n";
  });
}

void register_mc(CLI::App& app) {
  register_mc_command(app);
  register_skin_table_command(app);
  register_random_walk_command(app);
  register_validate_command(app);
}

SKIN_REGISTER_COMMAND(60, register_mc);

}  // namespace skin::cli
