// skin export: the units, the options and the entry points (export.hpp). The targets are in the
// registry (registry.cpp), each defined in its family's file; docs/export.md gives every mapping
// and its source.
#include "skin/export/export.hpp"

#include <algorithm>
#include <cmath>

#include "target.hpp"
#include "skin/util/charconv.hpp"
#include "skin/util/error.hpp"

namespace skin::exporting {

using skin::util::InputError;
using skin::util::ProgressCallback;
using skin::util::format_number;

using skin::transport::ProfileSolver;

using skin::physics::SkinParameters;
using skin::physics::parameter_info;

using detail::Reference;

// ---------------------------------------------------------------------------------------------
// Units

std::string_view unit_name(Unit u) { return u == Unit::mm ? "mm" : u == Unit::cm ? "cm" : "m"; }
std::string_view unit_long_name(Unit u) {
  return u == Unit::mm ? "millimeter" : u == Unit::cm ? "centimeter" : "meter";
}
double per_mm(Unit u) { return u == Unit::mm ? 1.0 : u == Unit::cm ? 0.1 : 0.001; }
Unit parse_unit(std::string_view text, std::string_view what) {
  if (text == "mm") return Unit::mm;
  if (text == "cm") return Unit::cm;
  if (text == "m") return Unit::m;
  throw InputError(std::string(what) + " = '" + std::string(text) +
                   "' is not a unit: must be mm, cm or m");
}

void Options::validate() const {
  if (!(world_scale > 0) || !std::isfinite(world_scale))
    throw InputError("world-scale = " + format_number(world_scale) +
                     " is out of range: must be > 0 (scene units per unit)");
  auto identifier = [](const std::string& s) {
    if (s.empty() || s.size() > 64 || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    });
  };
  if (!identifier(name))
    throw InputError("name = '" + name +
                     "' is not allowed: letters, digits and _ (not first), at most 64");
  if (gaussians < 2 || gaussians > 8)
    throw InputError("gaussians = " + std::to_string(gaussians) + " is out of range: must be in [2, 8]");
  if (taps < 3 || taps > 63 || taps % 2 == 0)
    throw InputError("taps = " + std::to_string(taps) + " is out of range: must be odd, in [3, 63]");
}

namespace {

Options checked(const Options& in) {
  Options o = in;
  if (o.stem.empty()) o.stem = o.name;
  o.validate();
  return o;
}

Export run(const Target& target, const Reference& ref, const Options& o,
           const detail::MapsFit* mf) {
  const detail::Context ctx{target, ref, o, o.unit.value_or(target.default_unit), mf};
  return detail::find_spec(target.name).write(ctx);
}

}  // namespace

struct Prepared {
  Reference ref;
};

std::shared_ptr<const Prepared> prepare(const SkinParameters& parameters,
                                        const transport::Model& model, const ProgressCallback& progress) {
  parameters.validate();
  ProfileSolver solver(detail::reference_radii());
  return std::make_shared<const Prepared>(Prepared{detail::make_reference(parameters, model, solver, progress, true)});
}

std::size_t prepare_solves(const SkinParameters& parameters, const transport::Model& model) {
  return skin::model::skin_profile_solves(parameters, detail::reference_grid(), model);
}

std::size_t prepare_wavelengths() { return detail::reference_grid().size(); }

Export export_prepared(std::string_view target_name, const Prepared& ours, const Options& options) {
  const Target& target = find_target(target_name);
  return run(target, ours.ref, checked(options), nullptr);
}

Export export_skin(std::string_view target_name, const SkinParameters& parameters,
                   const transport::Model& model, const Options& options_in,
                   const ParameterMapsInput* maps, const ProgressCallback& progress) {
  const Target& target = find_target(target_name);
  const Options o = checked(options_in);
  parameters.validate();
  if (!maps) return run(target, prepare(parameters, model, progress)->ref, o, nullptr);
  require_textures(target);
  // The single-material values are those of the maps' mean texel.
  SkinParameters p = parameters;
  const detail::MapsFit mf =
      detail::fit_maps(detail::find_spec(target.name).texel, parameters, model, *maps, progress);
  for (std::size_t k = 0; k < maps->keys.size(); ++k) {
    double sum = 0;
    for (float v : maps->values[k]) sum += v;
    p.*(parameter_info(maps->keys[k], maps->path).member) =
        sum / static_cast<double>(maps->values[k].size());
  }
  Export e = run(target, prepare(p, model)->ref, o, &mf);
  e.report.texels = mf.distinct;
  e.report.max_delta_e_2000 = mf.max_delta_e;
  e.report.notes.push_back("single values are those of the maps' mean texel; the textures hold "
                           "each texel's own fit");
  return e;
}

}  // namespace skin::exporting
