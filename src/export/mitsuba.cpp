// Mitsuba 3: the two layers themselves as nested homogeneous media in a rough dielectric, no fit
// (docs/export.md, "Volumetric targets").
#include <sstream>

#include "report.hpp"
#include "skin/util/escape.hpp"

namespace skin::exporting::detail {

using skin::model::skin_layer_stacks;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

namespace {

Export write(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  const SkinParameters& p = ref.parameters;
  const WavelengthGrid grid = spectral_grid();
  const double scale = ctx.scale();
  const std::vector<LayerStack> layers = skin_layer_stacks(p, grid);
  Export e;
  // The media are our layers themselves: the target's transport is exact up to its noise; what
  // differs is only the specular lobe (a dielectric, without the oiliness scale).
  e.report = fit_report(
      ctx,
      "Mitsuba 3 volumetric path tracing of our two layers (homogeneous media, "
      "HG phase function) inside a rough dielectric: no fit",
      ref.R_d, ref.R);
  e.report.notes.push_back(
      "the media are the two layers themselves: Mitsuba's volumetric path tracer solves their "
      "transport exactly up to Monte Carlo noise, where this project's accurate solver agrees "
      "with Monte Carlo to about 1 % in R_d; the error columns are zero by construction");
  if (p.oiliness != 1.0)
    e.report.notes.push_back("the rough dielectric's specular lobe is not scaled by oiliness (" +
                             num(p.oiliness) + ")");
  std::ostringstream x;
  // Ids NAME_epidermis, ...: the name escaped (and checked) for Mitsuba, the suffixes plain.
  const std::string name = util::escape::mitsuba_attribute(o.name, kName);
  auto spectrum = [&](const std::string& quantity, const std::vector<double>& v) {
    std::string s = "        <spectrum name=\"" + quantity + "\" value=\"";
    for (std::size_t i = 0; i < grid.size(); ++i) {
      if (i) s += ", ";
      s += num(grid[i]);
      s += ':';
      s += num(v[i]);
    }
    return s + "\"/>\n";
  };
  x << "<?xml version=\"1.0\"?>\n<!--\n" << header_lines("   ", e, ctx)
    << "   Media: sigma_t in 1/" << unit_name(unit)
    << ", albedo; use a spectral variant (e.g. scalar_spectral) and the volpath integrator.\n"
    << "   Include this fragment in a scene, or render it as it is with a camera and light added.\n-->\n";
  x << "<scene version=\"3.0.0\">\n";
  const char* names[2] = {"epidermis", "dermis"};
  for (int l = 0; l < 2; ++l) {
    std::vector<double> st(grid.size()), al(grid.size());
    for (std::size_t i = 0; i < grid.size(); ++i) {
      const Layer& L = layers[i].layers[l];
      st[i] = (L.sigma_a + L.sigma_s()) / scale;
      al[i] = L.sigma_s() / (L.sigma_a + L.sigma_s());
    }
    x << "    <medium type=\"homogeneous\" id=\"" << name << "_" << names[l] << "\">\n"
      << spectrum("sigma_t", st) << spectrum("albedo", al)
      << "        <float name=\"scale\" value=\"1\"/>\n"
      << "        <phase type=\"hg\"><float name=\"g\" value=\"" << num(layers[0].layers[l].g)
      << "\"/></phase>\n    </medium>\n";
  }
  x << "    <bsdf type=\"roughdielectric\" id=\"" << name << "_surface\">\n"
    << "        <string name=\"distribution\" value=\"beckmann\"/>\n"
    << "        <float name=\"alpha\" value=\"" << num(p.roughness) << "\"/>\n"
    << "        <float name=\"int_ior\" value=\"" << num(p.eta) << "\"/>\n"
    << "        <float name=\"ext_ior\" value=\"1.0\"/>\n    </bsdf>\n";
  x << "    <bsdf type=\"null\" id=\"" << name << "_interface\"/>\n";
  const double half = 50.0 * scale, te = p.epidermis_thickness * scale, depth = 20.0 * scale;
  auto cube = [&](double hx, double z0, double z1, const std::string& bsdf,
                  const std::string& interior, const std::string& exterior) {
    std::ostringstream c;
    c << "    <shape type=\"cube\">\n        <transform name=\"to_world\">\n"
      << "            <scale x=\"" << num(hx) << "\" y=\"" << num(hx) << "\" z=\""
      << num(0.5 * (z1 - z0)) << "\"/>\n            <translate z=\"" << num(0.5 * (z0 + z1))
      << "\"/>\n        </transform>\n        <ref id=\"" << bsdf << "\"/>\n"
      << "        <ref name=\"interior\" id=\"" << interior << "\"/>\n";
    if (!exterior.empty()) c << "        <ref name=\"exterior\" id=\"" << exterior << "\"/>\n";
    c << "    </shape>\n";
    return c.str();
  };
  x << "    <!-- Example: a slab 10 cm wide, the epidermis on a 2 cm deep dermis, top at z = 0. -->\n";
  x << cube(half, -depth, 0.0, name + "_surface", name + "_epidermis", "");
  x << cube(half - 0.5 * te, -depth + 0.5 * te, -te, name + "_interface", name + "_dermis",
            name + "_epidermis");
  x << "</scene>\n";
  e.files.push_back({"", x.str(), false});
  return e;
}

}  // namespace

TargetSpec mitsuba3_target() {
  return {"mitsuba3", "Mitsuba 3 XML: the two layers as nested homogeneous media in a rough dielectric",
          ".xml", Unit::m, write};
}

}  // namespace skin::exporting::detail
