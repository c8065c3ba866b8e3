// pbrt-v4: the 'subsurface' material of an effective homogeneous half-space fitted per
// wavelength, and the two layers themselves as nested media (docs/export.md, "Volumetric
// targets").
#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "report.hpp"
#include "skin/color/color.hpp"
#include "skin/util/escape.hpp"

namespace skin::exporting::detail {

using skin::transport::ProfileSolver;
using skin::transport::RadialResponse;
using skin::transport::RgbProfile;
using skin::transport::SpectralProfile;

using skin::model::skin_layer_stacks;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

namespace {

std::string pbrt_spectrum(const WavelengthGrid& g, const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < g.size(); ++i) {
    s += ' ';
    s += num(g[i]);
    s += ' ';
    s += num(v[i]);
  }
  return s + " ]";
}

std::string spd_file(const WavelengthGrid& g, const std::vector<double>& v, const std::string& what) {
  std::string s = "# " + what + "\n";
  for (std::size_t i = 0; i < g.size(); ++i) {
    s += num(g[i]);
    s += ' ';
    s += num(v[i]);
    s += '\n';
  }
  return s;
}

Export write(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  ProfileSolver solver(reference_radii());
  const SkinParameters& p = ref.parameters;
  const transport::Model& model = *ref.model;
  const WavelengthGrid grid = spectral_grid();
  const double scale = ctx.scale();  // length per mm: coefficients / scale
  // Our spectral R_d and profiles, from the reference's own responses (no wavelength solved again).
  if (!ref.spectral || !(ref.spectral->grid == grid)) throw std::logic_error("pbrt-v4 export: the reference has no spectral profile");
  const SpectralProfile& ours = *ref.spectral;
  // Effective single layer per wavelength: alpha' from R_d, sigma_t' from the mean radius, for a
  // homogeneous half-space with our eta and g through the same transport model (pbrt-v4 computes
  // its profile by photon beam diffusion, an approximation of the same transport).
  std::vector<double> sa(grid.size()), ss(grid.size());
  std::vector<LayerStack> stacks(grid.size());
  bool clamped = false;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    auto half_space = [&](double alpha_prime, double sigma_t_prime) {
      Layer l;
      l.sigma_s_prime = alpha_prime * sigma_t_prime;
      l.sigma_a = sigma_t_prime - l.sigma_s_prime;
      l.eta = p.eta;
      l.g = p.g;
      return LayerStack{{l}, 1.0, 1.0};
    };
    auto R = [&](double a) { return model.R_d(half_space(a, 1.0)); };
    const double target = ours.R_d[i];
    if (target > R(0.9999)) clamped = true;
    const double a = invert_increasing(R, target, 1e-4, 0.9999);
    const std::unique_ptr<RadialResponse> resp = model.response(half_space(a, 1.0));
    const std::vector<double> prof = solver.profile(*resp);
    const double m1 = mean_radius(solver.radii(), prof);
    std::vector<double> ours_i(solver.radii().size());
    for (std::size_t j = 0; j < ours_i.size(); ++j) ours_i[j] = std::max(ours.at(i, j), 0.0);
    const double m = mean_radius(solver.radii(), ours_i);
    const double sigma_t_prime = m > 0 ? m1 / m : 1.0;  // [1/mm]
    stacks[i] = half_space(a, sigma_t_prime);
    sa[i] = stacks[i].layers[0].sigma_a;
    ss[i] = stacks[i].layers[0].sigma_s();
  }
  // The target's RGB profile and colour: the effective layer through the same solver.
  std::vector<std::unique_ptr<RadialResponse>> responses;
  std::vector<const RadialResponse*> ptrs;
  for (const LayerStack& s : stacks) {
    responses.push_back(model.response(s));
    ptrs.push_back(responses.back().get());
  }
  const color::Colorimetry cm(grid, color::find_illuminant(color::kSrgbWhite));
  const RgbProfile target = solver.rgb(ptrs, cm.srgb_weights());
  std::array<std::vector<double>, 3> R_t;
  for (int c = 0; c < 3; ++c) {
    R_t[c] = target.R[c];
    for (double& v : R_t[c]) v = std::max(v, 0.0);
  }
  Export e;
  e.report = fit_report(
      ctx,
      "pbrt-v4 'subsurface': a homogeneous half-space (sigma_a, sigma_s, g, eta) whose profile "
      "pbrt tabulates by photon beam diffusion; fitted per wavelength through this project's "
      "transport of the same half-space (R_d and mean exit radius matched)",
      {target.R_d[0], target.R_d[1], target.R_d[2]}, R_t);
  if (clamped) {
    e.report.representable = false;
    e.report.notes.push_back("at some wavelengths R_d is beyond what a half-space reaches");
  }
  e.report.notes.push_back(
      "the two-layer variant (.two-layer.pbrt) holds our layers themselves as nested media: a "
      "volumetric path tracer solves their transport without a fit");
  std::vector<double> sa_u(sa), ss_u(ss);
  for (double& v : sa_u) v /= scale;
  for (double& v : ss_u) v /= scale;
  std::vector<double> lambda(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) lambda[i] = grid[i];
  e.report.values = {{"lambda_nm", lambda},
                     {"sigma_a", sa_u},
                     {"sigma_s", ss_u},
                     {"g", {p.g}},
                     {"eta", {p.eta}},
                     {"roughness", {p.roughness}}};
  const std::string unit_text = "1/" + std::string(unit_name(unit));
  std::ostringstream s;
  s << header_lines("#", e, ctx);
  s << "# sigma_a, sigma_s in " << unit_text << " (spectra as wavelength [nm], value pairs).\n";
  const std::string name = util::escape::pbrt_string(o.name, kName);
  s << "MakeNamedMaterial " << name << "\n"
    << "    \"string type\" [ \"subsurface\" ]\n"
    << "    \"float eta\" [ " << num(p.eta) << " ]\n"
    << "    \"float g\" [ " << num(p.g) << " ]\n"
    << "    \"float roughness\" [ " << num(p.roughness) << " ]\n"
    << "    \"bool remaproughness\" [ false ]\n"
    << "    \"float scale\" [ 1 ]\n";
  if (o.spectra_files) {
    s << "    \"spectrum sigma_a\" " << util::escape::pbrt_string(o.stem + ".sigma_a.spd", kOutput) << "\n"
      << "    \"spectrum sigma_s\" " << util::escape::pbrt_string(o.stem + ".sigma_s.spd", kOutput) << "\n";
    e.files.push_back({"", "", false});  // placeholder, filled below
    e.files.push_back({".sigma_a.spd", spd_file(grid, sa_u, "sigma_a [" + unit_text + "]"), true});
    e.files.push_back({".sigma_s.spd", spd_file(grid, ss_u, "sigma_s [" + unit_text + "]"), true});
  } else {
    s << "    \"spectrum sigma_a\" " << pbrt_spectrum(grid, sa_u) << "\n"
      << "    \"spectrum sigma_s\" " << pbrt_spectrum(grid, ss_u) << "\n";
  }
  if (e.files.empty()) e.files.push_back({"", "", false});
  e.files[0].content = s.str();
  // Two layers as nested media.
  const std::vector<LayerStack> layers = skin_layer_stacks(p, grid);
  std::ostringstream t;
  t << header_lines("#", e, ctx);
  t << "# The two layers as nested homogeneous media (sigma in " << unit_text
    << "). Example: a slab of skin\n# 10 cm wide, the epidermis on a 2 cm deep dermis, its top at "
       "z = 0, inside a rough dielectric.\n";
  const char* names[2] = {"epidermis", "dermis"};
  for (int l = 0; l < 2; ++l) {
    std::vector<double> a(grid.size()), sc(grid.size());
    for (std::size_t i = 0; i < grid.size(); ++i) {
      a[i] = layers[i].layers[l].sigma_a / scale;
      sc[i] = layers[i].layers[l].sigma_s() / scale;
    }
    t << "MakeNamedMedium " << util::escape::pbrt_string(o.name + "_" + names[l], kName) << "\n"
      << "    \"string type\" [ \"homogeneous\" ]\n"
      << "    \"float g\" [ " << num(layers[0].layers[l].g) << " ]\n"
      << "    \"float scale\" [ 1 ]\n"
      << "    \"spectrum sigma_a\" " << pbrt_spectrum(grid, a) << "\n"
      << "    \"spectrum sigma_s\" " << pbrt_spectrum(grid, sc) << "\n";
  }
  const double half = 50.0 * scale, te = p.epidermis_thickness * scale, depth = 20.0 * scale;
  auto box = [&](double z0, double z1, double h) {
    std::ostringstream b;
    b << "    Shape \"trianglemesh\" \"point3 P\" [ " << -h << " " << -h << " " << z0 << "  " << h
      << " " << -h << " " << z0 << "  " << h << " " << h << " " << z0 << "  " << -h << " " << h
      << " " << z0 << "  " << -h << " " << -h << " " << z1 << "  " << h << " " << -h << " " << z1
      << "  " << h << " " << h << " " << z1 << "  " << -h << " " << h << " " << z1 << " ]\n"
      << "        \"integer indices\" [ 0 2 1 0 3 2  4 5 6 4 6 7  0 1 5 0 5 4  1 2 6 1 6 5  2 3 7 "
         "2 7 6  3 0 4 3 4 7 ]\n";
    return b.str();
  };
  const std::string epidermis = util::escape::pbrt_string(o.name + "_epidermis", kName);
  const std::string dermis = util::escape::pbrt_string(o.name + "_dermis", kName);
  t << "AttributeBegin\n    MediumInterface " << epidermis << " \"\"\n"
    << "    Material \"dielectric\" \"float eta\" [ " << num(p.eta) << " ] \"float roughness\" [ "
    << num(p.roughness) << " ] \"bool remaproughness\" [ false ]\n"
    << box(-depth, 0.0, half) << "AttributeEnd\n";
  t << "AttributeBegin\n    MediumInterface " << dermis << " " << epidermis
    << "\n    Material \"interface\"\n"
    << box(-depth + 0.5 * te, -te, half - 0.5 * te) << "AttributeEnd\n";
  e.files.push_back({".two-layer.pbrt", t.str(), false});
  return e;
}

}  // namespace

TargetSpec pbrt_v4_target() {
  return {"pbrt-v4",
          "pbrt-v4 'subsurface' material (effective single layer) and the two layers as nested "
          "media",
          ".pbrt", Unit::m, write};
}

}  // namespace skin::exporting::detail
