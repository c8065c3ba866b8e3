// skin export: fits and writers per target (export.hpp; docs/export.md gives every mapping and
// its source).
#include "skin/export/export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <numbers>
#include <sstream>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "reference.hpp"
#include "skin/color/color.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/transport/random_walk_table.hpp"
#include "skin/util/charconv.hpp"
#include "skin/util/error.hpp"
#include "skin/util/escape.hpp"

namespace skin::exporting {

using detail::Reference;
using json = nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// Units and targets

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

const std::vector<Target>& targets() {
  static const std::vector<Target> t = {
      {"openpbr", "MaterialX document with an OpenPBR Surface (open_pbr_surface)", ".mtlx", Unit::m,
       true},
      {"standard-surface", "MaterialX document with an Autodesk Standard Surface", ".mtlx", Unit::m,
       true},
      {"cycles", "Python script for Blender (3.x, 4.x) making a Principled BSDF material", ".py",
       Unit::m, true},
      {"unreal", "Unreal Engine Subsurface Profile (Burley): JSON and an editor Python script",
       ".json", Unit::cm, false},
      {"unity", "Unity HDRP Diffusion Profile: an editor C# script making the asset, and JSON",
       ".cs", Unit::m, false},
      {"pbrt-v4", "pbrt-v4 'subsurface' material (effective single layer) and the two layers as "
                  "nested media",
       ".pbrt", Unit::m, false},
      {"mitsuba3", "Mitsuba 3 XML: the two layers as nested homogeneous media in a rough "
                   "dielectric",
       ".xml", Unit::m, false},
      {"realtime", "sum-of-Gaussians fit and a separable screen-space kernel (JSON)", ".json",
       Unit::mm, false},
      {"profile", "the radial profile R(r) per channel as a table (CSV, JSON, 1-D EXR)", ".csv",
       Unit::mm, false},
  };
  return t;
}

std::string default_stem(const Target& target, std::string_view name) {
  return std::string(name) + "." + std::string(target.name);
}

std::string target_names_text() {
  std::string s;
  for (const Target& t : targets()) s += (s.empty() ? "" : ", ") + std::string(t.name);
  return s;
}

const Target& find_target(std::string_view name) {
  for (const Target& t : targets())
    if (t.name == name) return t;
  throw InputError("target = '" + std::string(name) + "' is unknown: must be one of " +
                   target_names_text());
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

// ---------------------------------------------------------------------------------------------
// Formatting

// The options names and paths come from, as messages name them: every name and path a writer
// puts into a file goes through the escaping function of the file's format (skin/util/escape.hpp)
// with one of these.
constexpr std::string_view kName = "name";
constexpr std::string_view kOutput = "output";
// A name or path for a JSON document (nlohmann-json escapes it when it writes the document):
// UTF-8 text, or an InputError naming `what`.
std::string json_text(const std::string& text, std::string_view what) {
  escape::require_utf8(text, what);
  return text;
}

// Every number an export writes carries 6 significant digits (num), in text and JSON alike
// (rounded): well above float precision of the renderers, well below the noise of the last bits
// in which two builds (compilers, libm, vectorisation: the CLI's and the web page's) differ, so
// that the files are the same byte for byte wherever they are made. Errors that vanish when the
// target matches exactly (a colour difference, a relative error) are rounded to 1e-6 absolutely
// (rounded_error): their noise around zero has no significant digits.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
double rounded(double v) {
  if (!std::isfinite(v)) return v;
  const std::string t = num(v);
  double r = v;
  skin::from_chars(t.data(), t.data() + t.size(), r);
  return r + 0.0;  // no -0
}
double rounded_error(double v) { return std::isfinite(v) ? std::round(v * 1e6) / 1e6 + 0.0 : v; }
// The document with every floating-point number rounded().
json rounded(json j) {
  if (j.is_number_float()) return rounded(j.get<double>());
  if (j.is_structured())
    for (auto& v : j) v = rounded(std::move(v));
  return j;
}
std::string triple(const Rgb& c, const char* sep = ", ") {
  return num(c.r) + sep + num(c.g) + sep + num(c.b);
}

// The surface term: DJ06's Torrance-Sparrow lobe with a Beckmann distribution of RMS slope
// m = roughness, scaled by rho_s = oiliness, Fresnel at eta. Targets with a GGX lobe and a
// "perceptual" roughness r (alpha = r^2) get r = sqrt(m): GGX and Beckmann of equal alpha have
// close widths near the peak (Walter et al. 2007).
double perceptual_roughness(const SkinParameters& p) { return std::sqrt(p.roughness); }
double fresnel_f0(double eta) {
  const double q = (eta - 1.0) / (eta + 1.0);
  return q * q;
}

// ---------------------------------------------------------------------------------------------
// Random-walk targets (Cycles, OpenPBR, Standard Surface): albedo A through the target's
// inversion alpha(A), the walk's total R(alpha) (data/random_walk_g0.csv), mean free path d.

struct WalkFit {
  Rgb A;         // the target's colour parameter (multiple-scattering albedo)
  Rgb alpha;     // single-scattering albedo the target derives from it
  Rgb d_mm;      // extinction mean free path 1 / sigma_t [mm]
  Rgb R_d;       // the target's diffuse reflectance (colour under uniform white light)
  std::array<std::vector<double>, 3> R;  // its profile [1/mm^2]
  bool clamped = false;
};

WalkFit fit_walk(const Reference& ref, double (*alpha_of_A)(double), double gain) {
  const transport::RandomWalkTable& table = transport::RandomWalkTable::builtin();
  WalkFit f;
  for (int c = 0; c < 3; ++c) {
    auto D = [&](double A) { return gain * table.reflectance(alpha_of_A(A)); };
    const double y = ref.R_d[c];
    if (y > D(1.0) || y < D(0.0)) f.clamped = true;
    const double A = detail::invert_increasing(D, y, 0.0, 1.0);
    const double alpha = alpha_of_A(A);
    const double m_rho = table.mean_rho(alpha);
    double d = ref.mean_radius[c] > 0 && m_rho > 0 ? ref.mean_radius[c] / m_rho : 1e-6;
    f.A[c] = A;
    f.alpha[c] = alpha;
    f.R_d[c] = D(A);
    auto profile = [&](double dd) {
      std::vector<double> rho(ref.radii.size());
      for (std::size_t j = 0; j < rho.size(); ++j) rho[j] = ref.radii.r[j] / dd;
      std::vector<double> R = table.density(alpha, rho);
      for (double& v : R) v /= dd * dd;
      return R;
    };
    // The table's mean (annulus centres) and that of its interpolated density differ by ~1 %:
    // one correction makes the written profile's mean radius the reference's.
    const double m_t = detail::mean_radius(ref.radii, profile(d));
    if (m_t > 0) d *= ref.mean_radius[c] / m_t;
    f.d_mm[c] = d;
    f.R[c] = profile(d);
  }
  return f;
}

double chiang(double A) { return chiang_alpha(A); }
double cycles_g0(double A) { return cycles_alpha(A, 0.0); }

// Cycles 3.x adds a retro-reflection lobe to the Principled BSDF's subsurface closure (the
// Disney diffuse retro-reflection, f = A / pi RR F_L, RR = 2 r cos^2 theta_d, F_L = (1 - cos
// theta_l)^5). Under uniform white light and seen along the normal it adds
// 2 r int_0^1 (1 + mu) (1 - mu)^5 mu dmu = (5 / 84) r of A (r: Principled roughness).
double cycles_retro_gain(double principled_roughness) {
  return 1.0 + 5.0 / 84.0 * principled_roughness;
}

// ---------------------------------------------------------------------------------------------
// Burley targets (Unity HDRP, Unreal): R(r) = A burley(d, r); the colour is A itself.

struct BurleyFit {
  Rgb A, d_mm, R_d;
  std::array<std::vector<double>, 3> R;
  bool clamped = false;
};

BurleyFit fit_burley(const Reference& ref) {
  BurleyFit f;
  for (int c = 0; c < 3; ++c) {
    f.A[c] = std::clamp(ref.R_d[c], 0.0, 1.0);
    if (f.A[c] != ref.R_d[c]) f.clamped = true;
    f.d_mm[c] = std::max(ref.mean_radius[c] / 2.5, 1e-6);  // mean radius 2.5 d
    f.R_d[c] = f.A[c];
    f.R[c].resize(ref.radii.size());
    for (std::size_t j = 0; j < ref.radii.size(); ++j)
      f.R[c][j] = f.A[c] * burley_profile(f.d_mm[c], ref.radii.r[j]);
  }
  return f;
}

// Christensen & Burley 2015, eq. 6 (perpendicular incidence): d = l / s(A) for the mean free
// path l; Unreal's Burley subsurface profile takes l (its "mean free path").
double burley_s_perpendicular(double A) { return 1.9 - A + 3.5 * (A - 0.8) * (A - 0.8); }

// ---------------------------------------------------------------------------------------------
// The fit report

FitReport base_report(std::string_view target, std::string model, Unit unit, const Reference& ref,
                      const Rgb& R_d_target, const std::array<std::vector<double>, 3>& R_target) {
  FitReport r;
  r.target = std::string(target);
  r.target_model = std::move(model);
  r.unit = unit;
  r.R_d_ours = ref.R_d;
  r.R_d_target = R_d_target;
  r.delta_e_2000 = detail::delta_e(ref.R_d, R_d_target);
  for (int c = 0; c < 3; ++c) {
    r.mean_radius_mm[c] = ref.mean_radius[c];
    r.profile_l1[c] = detail::relative_l1(ref.radii, R_target[c], ref.R[c]);
    const double m = detail::mean_radius(ref.radii, R_target[c]);
    r.mean_radius_error[c] = ref.mean_radius[c] > 0 ? m / ref.mean_radius[c] - 1.0 : 0.0;
  }
  return r;
}

std::vector<double> vec(const Rgb& c) { return {c.r, c.g, c.b}; }

// ---------------------------------------------------------------------------------------------
// Parameter maps: per distinct texel, the target's colour and radius.

struct TexelFit {
  Rgb color;      // the target's colour parameter (linear)
  Rgb radius_mm;  // its radius parameter, mm (before the unit)
  double delta_e = 0;
};

struct MapsFit {
  int width = 0, height = 0;
  std::vector<TexelFit> texels;  // width * height
  std::size_t distinct = 0;
  double max_delta_e = 0;
};

}  // namespace

namespace detail {
// One texel through a random-walk target: colour parameter A and the radius parameter in mm
// (Cycles: the Principled radius 4 pi d; OpenPBR / Standard Surface: d).
TexelFit texel_fit(std::string_view target, const Reference& ref) {
  const bool cycles = target == "cycles";
  const double gain = cycles ? cycles_retro_gain(perceptual_roughness(ref.parameters)) : 1.0;
  const WalkFit w = fit_walk(ref, cycles ? cycles_g0 : chiang, gain);
  TexelFit t;
  t.color = w.A;
  for (int c = 0; c < 3; ++c) t.radius_mm[c] = (cycles ? 4.0 * std::numbers::pi : 1.0) * w.d_mm[c];
  t.delta_e = delta_e(ref.R_d, w.R_d);
  return t;
}
}  // namespace detail

namespace {

MapsFit fit_maps(std::string_view target, const SkinParameters& base,
                 const transport::Model& model, const ParameterMapsInput& maps,
                 const ProgressCallback& progress) {
  MapsFit out;
  out.width = maps.width;
  out.height = maps.height;
  const std::size_t n = static_cast<std::size_t>(maps.width) * maps.height;
  std::vector<const ParameterInfo*> info;
  for (const std::string& k : maps.keys) info.push_back(&parameter_info(k, maps.path));
  // Distinct texels (exact float values), in first-seen order.
  std::map<std::vector<float>, std::size_t> index;
  std::vector<std::vector<float>> distinct;
  std::vector<std::size_t> texel_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<float> key(maps.keys.size());
    for (std::size_t k = 0; k < key.size(); ++k) key[k] = maps.values[k][i];
    const auto [it, inserted] = index.emplace(key, distinct.size());
    if (inserted) distinct.push_back(key);
    texel_of[i] = it->second;
  }
  std::vector<SkinParameters> sets(distinct.size(), base);
  for (std::size_t d = 0; d < distinct.size(); ++d) {
    for (std::size_t k = 0; k < info.size(); ++k) {
      const double v = distinct[d][k];
      try {
        info[k]->check(v);
      } catch (const InputError& err) {
        throw InputError(maps.path + ": " + err.what());
      }
      sets[d].*(info[k]->member) = v;
    }
    sets[d].validate();
  }
  std::vector<TexelFit> fits(distinct.size());
  tbb::enumerable_thread_specific<ProfileSolver> solvers(
      [] { return ProfileSolver(detail::reference_radii()); });
  std::mutex m;
  std::size_t done = 0;
  tbb::parallel_for(std::size_t{0}, distinct.size(), [&](std::size_t d) {
    const Reference ref = detail::make_reference(sets[d], model, solvers.local());
    fits[d] = detail::texel_fit(target, ref);
    if (progress) {
      std::lock_guard lock(m);
      progress(++done, distinct.size());
    }
  });
  out.texels.resize(n);
  for (std::size_t i = 0; i < n; ++i) out.texels[i] = fits[texel_of[i]];
  out.distinct = distinct.size();
  for (const TexelFit& f : fits) out.max_delta_e = std::max(out.max_delta_e, f.delta_e);
  return out;
}

// The two textures of a maps fit: colour (PNG, sRGB-encoded) and radius (EXR, linear, in the
// file's unit).
void add_textures(Export& e, const MapsFit& mf, double radius_scale) {
  ImageFile color{".subsurface_color.png", {}, image::Image(mf.width, mf.height), true};
  ImageFile radius{".subsurface_radius.exr", {mf.width, mf.height, {"R", "G", "B"}, {}}, {}, true};
  for (int c = 0; c < 3; ++c) radius.planes.values.emplace_back(mf.texels.size());
  for (std::size_t i = 0; i < mf.texels.size(); ++i) {
    const int x = static_cast<int>(i % mf.width), y = static_cast<int>(i / mf.width);
    color.rgb.set(x, y, mf.texels[i].color);
    for (int c = 0; c < 3; ++c)
      radius.planes.values[c][i] = static_cast<float>(mf.texels[i].radius_mm[c] * radius_scale);
  }
  e.images.push_back(std::move(color));
  e.images.push_back(std::move(radius));
}

std::string header_lines(const char* prefix, const Export& e, const SkinParameters& p,
                         const transport::Model& model, Unit unit, double world_scale) {
  std::ostringstream os;
  os << prefix << " Spectral Skin export for " << e.report.target << " (docs/export.md).\n";
  os << prefix << " Skin: melanin " << num(p.melanin) << ", melanin_blend " << num(p.melanin_blend)
     << ", hemoglobin " << num(p.hemoglobin) << ", oiliness " << num(p.oiliness) << "; solver "
     << model.name() << ".\n";
  os << prefix << " Colours: linear Rec.709 (sRGB primaries, D65). Lengths: " << unit_name(unit);
  if (world_scale != 1.0) os << " x world scale " << num(world_scale);
  os << ".\n";
  os << prefix << " Target model: " << e.report.target_model << "\n";
  const auto& l1 = e.report.profile_l1;
  os << prefix << " Fit: colour dE2000 " << num(rounded_error(e.report.delta_e_2000))
     << ", profile L1 (R, G, B) "
     << triple({rounded_error(l1[0]), rounded_error(l1[1]), rounded_error(l1[2])})
     << "; full report in the .fit.json beside this file.\n";
  for (const std::string& n : e.report.notes) os << prefix << " Note: " << n << "\n";
  return os.str();
}

// ---------------------------------------------------------------------------------------------
// Writers

Export export_materialx(bool openpbr, const Reference& ref, const Options& o, Unit unit,
                        const MapsFit* mf) {
  const WalkFit w = fit_walk(ref, chiang, 1.0);
  Export e;
  const double scale = per_mm(unit) * o.world_scale;
  const Rgb d = {w.d_mm.r * scale, w.d_mm.g * scale, w.d_mm.b * scale};
  const double d_max = std::max({d.r, d.g, d.b});
  const Rgb d_rel = {d.r / d_max, d.g / d_max, d.b / d_max};
  const SkinParameters& p = ref.parameters;
  e.report = base_report(openpbr ? "openpbr" : "standard-surface",
                         std::string(openpbr ? "OpenPBR" : "Standard Surface") +
                             " random-walk subsurface: radius = extinction mean free path, colour = "
                             "multiple-scattering albedo inverted by Chiang et al. 2016 eq. 3, "
                             "isotropic walk, index-matched boundary",
                         unit, ref, w.R_d, w.R);
  if (w.clamped) {
    e.report.representable = false;
    e.report.notes.push_back("a channel's R_d is beyond the albedo range the target reaches");
  }
  e.report.values = {{"subsurface_color", vec(w.A)},
                     {"subsurface_radius", {d_max}},
                     {"subsurface_radius_scale", vec(d_rel)},
                     {"specular_ior", {p.eta}},
                     {"specular_roughness", {perceptual_roughness(p)}},
                     {"specular_weight", {p.oiliness}}};
  std::ostringstream x;
  const std::string material = escape::xml_attribute(o.name, kName);
  const std::string shader = material + "_surface";
  x << "<?xml version=\"1.0\"?>\n";
  x << "<materialx version=\"" << (openpbr ? "1.39" : "1.38") << "\" colorspace=\"lin_rec709\">\n";
  x << "  <!--\n" << header_lines("   ", e, p, *ref.model, unit, o.world_scale) << "  -->\n";
  const std::string u = std::string(unit_long_name(unit));
  auto input = [&](const std::string& name, const std::string& type, const std::string& value,
                   const std::string& extra = "") {
    x << "    <input name=\"" << name << "\" type=\"" << type << "\" value=\"" << value << "\""
      << extra << " />\n";
  };
  if (mf) {
    x << "  <image name=\"" << material << "_subsurface_color_map\" type=\"color3\">\n"
      << "    <input name=\"file\" type=\"filename\" value=\""
      << escape::xml_attribute(o.stem + ".subsurface_color.png", kOutput)
      << "\" colorspace=\"srgb_texture\" />\n  </image>\n";
    x << "  <image name=\"" << material << "_subsurface_radius_map\" type=\"color3\">\n"
      << "    <!-- linear data in " << u << " (no colour space) -->\n"
      << "    <input name=\"file\" type=\"filename\" value=\""
      << escape::xml_attribute(o.stem + ".subsurface_radius.exr", kOutput) << "\" />\n  </image>\n";
  }
  const std::string dist = " unittype=\"distance\" unit=\"" + u + "\"";
  auto connect = [&](const std::string& name, const std::string& type, const std::string& node) {
    x << "    <input name=\"" << name << "\" type=\"" << type << "\" nodename=\"" << node
      << "\" />\n";
  };
  // The two schemas take the same inputs under their own names; the radius is a scalar (with the
  // distance unit) times a colour in both, in opposite roles (OpenPBR: subsurface_radius is the
  // scalar, Standard Surface: subsurface_scale is).
  struct Schema {
    const char *node, *base, *specular, *ior, *subsurface, *anisotropy, *radius_scalar,
        *radius_colour;
    bool scalar_first;
  };
  const Schema s = openpbr
                       ? Schema{"open_pbr_surface", "base_weight", "specular_weight", "specular_ior",
                                "subsurface_weight", "subsurface_scatter_anisotropy",
                                "subsurface_radius", "subsurface_radius_scale", true}
                       : Schema{"standard_surface", "base", "specular", "specular_IOR",
                                "subsurface", "subsurface_anisotropy", "subsurface_scale",
                                "subsurface_radius", false};
  x << "  <" << s.node << " name=\"" << shader << "\" type=\"surfaceshader\">\n";
  input(s.base, "float", "1");
  if (mf) connect("base_color", "color3", material + "_subsurface_color_map");
  else input("base_color", "color3", triple(w.A));
  input(s.specular, "float", num(p.oiliness));
  input("specular_roughness", "float", num(perceptual_roughness(p)));
  input(s.ior, "float", num(p.eta));
  input(s.subsurface, "float", "1");
  if (mf) connect("subsurface_color", "color3", material + "_subsurface_color_map");
  else input("subsurface_color", "color3", triple(w.A));
  auto scalar = [&] { input(s.radius_scalar, "float", mf ? "1" : num(d_max), dist); };
  auto colour = [&] {
    if (mf) connect(s.radius_colour, "color3", material + "_subsurface_radius_map");
    else input(s.radius_colour, "color3", triple(d_rel));
  };
  if (s.scalar_first) {
    scalar();
    colour();
  } else {
    colour();
    scalar();
  }
  input(s.anisotropy, "float", "0");
  x << "  </" << s.node << ">\n";
  x << "  <surfacematerial name=\"" << material << "\" type=\"material\">\n"
    << "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"" << shader
    << "\" />\n  </surfacematerial>\n</materialx>\n";
  e.files.push_back({"", x.str(), false});
  if (mf) add_textures(e, *mf, scale);
  return e;
}

Export export_cycles(const Reference& ref, const Options& o, Unit unit, const MapsFit* mf) {
  const SkinParameters& p = ref.parameters;
  const double rough = perceptual_roughness(p);
  const WalkFit w = fit_walk(ref, cycles_g0, cycles_retro_gain(rough));
  const double scale = per_mm(unit) * o.world_scale;
  // Cycles' Random Walk (Fixed Radius) in 3.x, Random Walk in 4.x, scale the radius by 1 / (4 pi)
  // to get the mean free path (bssrdf_setup_radius): radius = 4 pi d.
  const double four_pi = 4.0 * std::numbers::pi;
  const Rgb radius = {four_pi * w.d_mm.r * scale, four_pi * w.d_mm.g * scale,
                      four_pi * w.d_mm.b * scale};
  Export e;
  e.report = base_report(
      "cycles",
      "Cycles random walk (3.x 'Random Walk (Fixed Radius)', 4.x 'Random Walk'): mean free path = "
      "radius / (4 pi), albedo through Cycles' remap at anisotropy 0, cosine-weighted entry, "
      "index-matched walk; 3.x adds the Principled retro-reflection lobe ((5/84) roughness of the "
      "albedo at normal view)",
      unit, ref, w.R_d, w.R);
  if (w.clamped) {
    e.report.representable = false;
    e.report.notes.push_back("a channel's R_d is beyond the albedo range Cycles' walk reaches");
  }
  const double specular_3x = p.oiliness * fresnel_f0(p.eta) / 0.08;
  e.report.values = {{"subsurface_color", vec(w.A)},
                     {"subsurface_radius", vec(radius)},
                     {"roughness", {rough}},
                     {"ior", {p.eta}},
                     {"specular", {specular_3x}},
                     {"specular_ior_level", {0.5 * p.oiliness}}};
  std::ostringstream s;
  s << header_lines("#", e, p, *ref.model, unit, o.world_scale);
  s << "# Run: blender --background --python THIS_FILE [-- --blend OUT.blend], or from Blender's\n"
       "# text editor. Creates (or updates) the material NAME and returns it from make_material().\n"
       "import os\nimport sys\n\nimport bpy\n\n";
  s << "NAME = " << escape::python_string(o.name, kName) << "\n";
  s << "SUBSURFACE_COLOR = (" << triple(w.A) << ")  # linear Rec.709\n";
  s << "SUBSURFACE_RADIUS = (" << triple(radius) << ")  # " << unit_name(unit)
    << " (Blender units): 4 pi x mean free path\n";
  s << "ROUGHNESS = " << num(rough) << "\n";
  s << "IOR = " << num(p.eta) << "\n";
  s << "SPECULAR = " << num(specular_3x) << "  # 3.x: F0 / 0.08 x oiliness\n";
  s << "SPECULAR_IOR_LEVEL = " << num(0.5 * p.oiliness) << "  # 4.x: 0.5 = the IOR's own F0\n";
  if (mf)
    s << "COLOR_MAP = " << escape::python_string(o.stem + ".subsurface_color.png", kOutput)
      << "  # sRGB\n"
      << "RADIUS_MAP = " << escape::python_string(o.stem + ".subsurface_radius.exr", kOutput)
      << "  # linear, Blender units\n";
  else
    s << "COLOR_MAP = None\nRADIUS_MAP = None\n";
  s << R"PY(

def _set(node, names, value):
    """Sets the first input of `names` that this Blender version has; returns its name."""
    for name in names:
        if name in node.inputs:
            node.inputs[name].default_value = value
            return name
    raise RuntimeError("Principled BSDF has none of the inputs %s" % (names,))


def _image(nodes, links, path, non_color, socket):
    here = os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals() else os.getcwd()
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = bpy.data.images.load(os.path.join(here, path), check_existing=True)
    tex.image.colorspace_settings.name = "Non-Color" if non_color else "sRGB"
    tex.interpolation = "Closest"
    links.new(tex.outputs["Color"], socket)
    return tex


def make_material():
    version = bpy.app.version
    if version < (3, 0, 0):
        raise RuntimeError("Spectral Skin's Cycles export needs Blender 3.0 or later, not %s"
                           % bpy.app.version_string)
    mat = bpy.data.materials.get(NAME) or bpy.data.materials.new(NAME)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    bsdf = nodes.new("ShaderNodeBsdfPrincipled")
    links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    color = SUBSURFACE_COLOR + (1.0,)
    if version >= (4, 0, 0):
        bsdf.subsurface_method = "RANDOM_WALK"  # 4.x: the fixed-radius walk, radius / (4 pi)
        _set(bsdf, ["Base Color"], color)
        _set(bsdf, ["Subsurface Weight"], 1.0)
        _set(bsdf, ["Subsurface Scale"], 1.0)
        _set(bsdf, ["Specular IOR Level"], SPECULAR_IOR_LEVEL)
    else:
        bsdf.subsurface_method = "RANDOM_WALK_FIXED_RADIUS"
        _set(bsdf, ["Base Color"], color)
        _set(bsdf, ["Subsurface"], 1.0)
        _set(bsdf, ["Subsurface Color"], color)
        _set(bsdf, ["Specular"], SPECULAR)
        _set(bsdf, ["Subsurface IOR"], IOR)
    _set(bsdf, ["Subsurface Radius"], SUBSURFACE_RADIUS)
    _set(bsdf, ["Subsurface Anisotropy"], 0.0)
    _set(bsdf, ["Roughness"], ROUGHNESS)
    _set(bsdf, ["IOR"], IOR)
    if COLOR_MAP:
        _image(nodes, links, COLOR_MAP, False, bsdf.inputs["Base Color"])
        if "Subsurface Color" in bsdf.inputs:
            _image(nodes, links, COLOR_MAP, False, bsdf.inputs["Subsurface Color"])
    if RADIUS_MAP:
        _image(nodes, links, RADIUS_MAP, True, bsdf.inputs["Subsurface Radius"])
    return mat


if __name__ == "__main__":
    material = make_material()
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if "--blend" in argv:
        bpy.ops.wm.save_as_mainfile(filepath=argv[argv.index("--blend") + 1])
    print("spectral_skin: material '%s' ready (Blender %s)" % (material.name, bpy.app.version_string))
)PY";
  e.files.push_back({"", s.str(), false});
  if (mf) add_textures(e, *mf, scale);
  return e;
}

json report_values_json(const FitReport& r) {
  json v = json::object();
  for (const auto& [k, vals] : r.values) v[k] = vals.size() == 1 ? json(vals[0]) : json(vals);
  return v;
}

Export export_unreal(const Reference& ref, const Options& o, Unit unit) {
  const BurleyFit b = fit_burley(ref);
  const SkinParameters& p = ref.parameters;
  Rgb l_cm;
  for (int c = 0; c < 3; ++c) l_cm[c] = burley_s_perpendicular(b.A[c]) * b.d_mm[c] * 0.1;
  const double l_max = std::max({l_cm.r, l_cm.g, l_cm.b});
  const Rgb l_rel = {l_cm.r / l_max, l_cm.g / l_max, l_cm.b / l_max};
  // Unreal's world unit is a centimetre; world_unit_scale = cm per world unit of the scene.
  const double world_unit_scale = 1.0 / (per_mm(unit) * 10.0) / o.world_scale;
  Export e;
  e.report = base_report("unreal",
                         "Unreal Burley subsurface profile: Christensen-Burley normalized diffusion, "
                         "R = A (e^{-r/d} + e^{-r/3d}) / (8 pi d r), d = mean free path / s(A), "
                         "s(A) = 1.9 - A + 3.5 (A - 0.8)^2; surface albedo = A",
                         unit, ref, b.R_d, b.R);
  e.report.values = {{"surface_albedo", vec(b.A)},
                     {"mean_free_path_color", vec(l_rel)},
                     {"mean_free_path_distance", {l_max}},
                     {"world_unit_scale", {world_unit_scale}},
                     {"tint", {1.0, 1.0, 1.0}},
                     {"transmission_tint_color", {1.0, 1.0, 1.0}},
                     {"ior", {p.eta}}};
  json j;
  j["format"] = "Spectral Skin export: Unreal Engine Subsurface Profile (Burley)";
  j["name"] = json_text(o.name, kName);
  j["color_space"] = "linear Rec.709 (sRGB primaries, D65)";
  j["units"] = {{"mean_free_path_distance", "cm"}, {"world_unit_scale", "cm per world unit"}};
  j["settings"] = report_values_json(e.report);
  j["settings"]["enable_burley"] = true;
  e.files.push_back({"", rounded(j).dump(2) + "\n", false});
  std::ostringstream s;
  s << header_lines("#", e, p, *ref.model, unit, o.world_scale);
  s << "# Run inside the Unreal Editor (Python Editor Script Plugin): creates or updates the\n"
       "# Subsurface Profile asset /Game/NAME.\nimport unreal\n\n";
  s << "NAME = " << escape::python_string(o.name, kName) << "\n";
  s << "SETTINGS = {\n"
    << "    \"enable_burley\": True,\n"
    << "    \"surface_albedo\": unreal.LinearColor(" << triple(b.A) << ", 1.0),\n"
    << "    \"mean_free_path_color\": unreal.LinearColor(" << triple(l_rel) << ", 1.0),\n"
    << "    \"mean_free_path_distance\": " << num(l_max) << ",  # cm\n"
    << "    \"world_unit_scale\": " << num(world_unit_scale) << ",\n"
    << "    \"tint\": unreal.LinearColor(1.0, 1.0, 1.0, 1.0),\n"
    << "    \"transmission_tint_color\": unreal.LinearColor(1.0, 1.0, 1.0, 1.0),\n"
    << "    \"ior\": " << num(p.eta) << ",\n}\n";
  s << R"PY(

def make_profile(path="/Game"):
    tools = unreal.AssetToolsHelpers.get_asset_tools()
    asset = unreal.EditorAssetLibrary.load_asset(path + "/" + NAME)
    if asset is None:
        asset = tools.create_asset(NAME, path, unreal.SubsurfaceProfile, unreal.SubsurfaceProfileFactory())
    settings = asset.get_editor_property("settings")
    missing = []
    for key, value in SETTINGS.items():
        try:
            settings.set_editor_property(key, value)
        except Exception:  # a property this engine version does not have
            missing.append(key)
    asset.set_editor_property("settings", settings)
    unreal.EditorAssetLibrary.save_loaded_asset(asset)
    if missing:
        unreal.log_warning("spectral_skin: not set in this engine version: " + ", ".join(missing))
    return asset


if __name__ == "__main__":
    make_profile()
)PY";
  e.files.push_back({".py", s.str(), false});
  return e;
}

Export export_unity(const Reference& ref, const Options& o, Unit unit) {
  const BurleyFit b = fit_burley(ref);
  const SkinParameters& p = ref.parameters;
  const double d_max = std::max({b.d_mm.r, b.d_mm.g, b.d_mm.b});
  const Rgb d_rel = {b.d_mm.r / d_max, b.d_mm.g / d_max, b.d_mm.b / d_max};
  // HDRP: scattering distance in mm; world scale = metres per world unit.
  const double world_scale = per_mm(unit) == 1.0 ? 0.001 : per_mm(unit) == 0.1 ? 0.01 : 1.0;
  const double world = world_scale / o.world_scale;
  const double thickness_mm = p.epidermis_thickness + 5.0;
  Export e;
  e.report = base_report("unity",
                         "HDRP diffusion profile: Christensen-Burley normalized diffusion with shape "
                         "S = 1 / (scattering distance x multiplier), albedo = the material's base "
                         "colour (pre- and post-scatter)",
                         unit, ref, b.R_d, b.R);
  e.report.values = {{"base_color", vec(b.A)},
                     {"scattering_distance", vec(d_rel)},
                     {"scattering_distance_multiplier", {d_max}},
                     {"transmission_tint", {1.0, 1.0, 1.0}},
                     {"thickness_remap", {0.0, thickness_mm}},
                     {"ior", {p.eta}},
                     {"world_scale", {world}}};
  std::ostringstream s;
  s << header_lines("//", e, p, *ref.model, unit, o.world_scale);
  // The name is also the class's (Options::validate: an identifier); in strings it is escaped.
  s << "// Put this file in an Editor folder of an HDRP project; run Tools > Spectral Skin > "
       "Create " << o.name << ".\n// The material's base colour (linear): " << triple(b.A)
    << " (sRGB " << color::hex(color::srgb8(b.A)) << ").\n";
  s << "using UnityEditor;\nusing UnityEngine;\nusing UnityEngine.Rendering.HighDefinition;\n\n";
  s << "public static class SpectralSkin_" << o.name << "\n{\n";
  s << "    [MenuItem(" << escape::csharp_string("Tools/Spectral Skin/Create " + o.name, kName)
    << ")]\n";
  s << "    public static void Create()\n    {\n";
  s << "        var asset = ScriptableObject.CreateInstance<DiffusionProfileSettings>();\n";
  s << "        AssetDatabase.CreateAsset(asset, "
    << escape::csharp_string("Assets/" + o.name + ".asset", kName) << ");\n";
  s << "        var so = new SerializedObject(asset);\n";
  s << "        so.FindProperty(\"profile.scatteringDistance\").colorValue = new Color(" << num(d_rel.r)
    << "f, " << num(d_rel.g) << "f, " << num(d_rel.b) << "f, 1f);\n";
  s << "        so.FindProperty(\"profile.scatteringDistanceMultiplier\").floatValue = " << num(d_max)
    << "f; // mm\n";
  s << "        so.FindProperty(\"profile.transmissionTint\").colorValue = Color.white;\n";
  s << "        so.FindProperty(\"profile.thicknessRemap\").vector2Value = new Vector2(0f, "
    << num(thickness_mm) << "f); // mm\n";
  s << "        so.FindProperty(\"profile.ior\").floatValue = " << num(p.eta) << "f;\n";
  s << "        so.FindProperty(\"profile.worldScale\").floatValue = " << num(world)
    << "f; // metres per world unit\n";
  s << "        so.ApplyModifiedProperties();\n        AssetDatabase.SaveAssets();\n    }\n}\n";
  e.files.push_back({"", s.str(), false});
  json j;
  j["format"] = "Spectral Skin export: Unity HDRP Diffusion Profile";
  j["name"] = json_text(o.name, kName);
  j["color_space"] = "linear Rec.709 (sRGB primaries, D65)";
  j["units"] = {{"scattering_distance_multiplier", "mm"},
                {"thickness_remap", "mm"},
                {"world_scale", "m per world unit"}};
  j["profile"] = report_values_json(e.report);
  e.files.push_back({".json", rounded(j).dump(2) + "\n", false});
  return e;
}

// Spectra on the export grid (400-700 nm, 10 nm).
WavelengthGrid spectral_grid() { return WavelengthGrid(400.0, 700.0, 10.0); }

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

Export export_pbrt(const Reference& ref, const Options& o, Unit unit) {
  ProfileSolver solver(detail::reference_radii());
  const SkinParameters& p = ref.parameters;
  const transport::Model& model = *ref.model;
  const WavelengthGrid grid = spectral_grid();
  const double scale = per_mm(unit) * o.world_scale;  // length per mm: coefficients / scale
  // Our spectral R_d and profiles.
  const SpectralProfile ours = skin_spectral_profile(p, grid, solver, model);
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
    const double a = detail::invert_increasing(R, target, 1e-4, 0.9999);
    const std::unique_ptr<RadialResponse> resp = model.response(half_space(a, 1.0));
    const std::vector<double> prof = solver.profile(*resp);
    const double m1 = detail::mean_radius(solver.radii(), prof);
    std::vector<double> ours_i(solver.radii().size());
    for (std::size_t j = 0; j < ours_i.size(); ++j) ours_i[j] = std::max(ours.at(i, j), 0.0);
    const double m = detail::mean_radius(solver.radii(), ours_i);
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
  const color::Colorimetry cm(grid);
  const RgbProfile target = solver.rgb(ptrs, cm.srgb_weights());
  std::array<std::vector<double>, 3> R_t;
  for (int c = 0; c < 3; ++c) {
    R_t[c] = target.R[c];
    for (double& v : R_t[c]) v = std::max(v, 0.0);
  }
  Export e;
  e.report = base_report(
      "pbrt-v4",
      "pbrt-v4 'subsurface': a homogeneous half-space (sigma_a, sigma_s, g, eta) whose profile "
      "pbrt tabulates by photon beam diffusion; fitted per wavelength through this project's "
      "transport of the same half-space (R_d and mean exit radius matched)",
      unit, ref, {target.R_d[0], target.R_d[1], target.R_d[2]}, R_t);
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
  s << header_lines("#", e, p, model, unit, o.world_scale);
  s << "# sigma_a, sigma_s in " << unit_text << " (spectra as wavelength [nm], value pairs).\n";
  const std::string name = escape::pbrt_string(o.name, kName);
  s << "MakeNamedMaterial " << name << "\n"
    << "    \"string type\" [ \"subsurface\" ]\n"
    << "    \"float eta\" [ " << num(p.eta) << " ]\n"
    << "    \"float g\" [ " << num(p.g) << " ]\n"
    << "    \"float roughness\" [ " << num(p.roughness) << " ]\n"
    << "    \"bool remaproughness\" [ false ]\n"
    << "    \"float scale\" [ 1 ]\n";
  if (o.spectra_files) {
    s << "    \"spectrum sigma_a\" " << escape::pbrt_string(o.stem + ".sigma_a.spd", kOutput) << "\n"
      << "    \"spectrum sigma_s\" " << escape::pbrt_string(o.stem + ".sigma_s.spd", kOutput) << "\n";
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
  t << header_lines("#", e, p, model, unit, o.world_scale);
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
    t << "MakeNamedMedium " << escape::pbrt_string(o.name + "_" + names[l], kName) << "\n"
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
  const std::string epidermis = escape::pbrt_string(o.name + "_epidermis", kName);
  const std::string dermis = escape::pbrt_string(o.name + "_dermis", kName);
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

Export export_mitsuba(const Reference& ref, const Options& o, Unit unit) {
  const SkinParameters& p = ref.parameters;
  const WavelengthGrid grid = spectral_grid();
  const double scale = per_mm(unit) * o.world_scale;
  const std::vector<LayerStack> layers = skin_layer_stacks(p, grid);
  Export e;
  // The media are our layers themselves: the target's transport is exact up to its noise; what
  // differs is only the specular lobe (a dielectric, without the oiliness scale).
  e.report = base_report("mitsuba3",
                         "Mitsuba 3 volumetric path tracing of our two layers (homogeneous media, "
                         "HG phase function) inside a rough dielectric: no fit",
                         unit, ref, ref.R_d, ref.R);
  e.report.notes.push_back(
      "the media are the two layers themselves: Mitsuba's volumetric path tracer solves their "
      "transport exactly up to Monte Carlo noise, where this project's accurate solver agrees "
      "with Monte Carlo to about 1 % in R_d; the error columns are zero by construction");
  if (p.oiliness != 1.0)
    e.report.notes.push_back("the rough dielectric's specular lobe is not scaled by oiliness (" +
                             num(p.oiliness) + ")");
  std::ostringstream x;
  // Ids NAME_epidermis, ...: the name escaped (and checked) for Mitsuba, the suffixes plain.
  const std::string name = escape::mitsuba_attribute(o.name, kName);
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
  x << "<?xml version=\"1.0\"?>\n<!--\n" << header_lines("   ", e, p, *ref.model, unit, o.world_scale)
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

// Sum of Gaussians: R(r) ~ sum_k w_k G(v_k, r), G(v, r) = exp(-r^2 / 2v) / (2 pi v) (integrates
// to 1 over the plane), variances shared by the channels on a geometric ladder v_k = v_0 q^k,
// weights >= 0 per channel by least squares of 2 pi r R(r) in d(ln r); the ladder (v_0, q) by a
// search minimizing the summed relative L1 error (d'Eon, Luebke & Enderton 2007).
struct Gaussians {
  std::vector<double> v;                 // [mm^2]
  std::array<std::vector<double>, 3> w;  // per channel
  std::array<std::vector<double>, 3> R;  // the fitted profile
  double error = 0;
};

Gaussians fit_gaussians(const Reference& ref, int n) {
  const RadialGrid& radii = ref.radii;
  const std::size_t J = radii.size();
  auto fit_ladder = [&](double v0, double q) {
    Gaussians g;
    for (int k = 0; k < n; ++k) g.v.push_back(v0 * std::pow(q, k));
    Eigen::MatrixXd A(J, n);
    for (std::size_t j = 0; j < J; ++j) {
      const double r = radii.r[j];
      for (int k = 0; k < n; ++k)
        A(j, k) = r * r * std::exp(-r * r / (2 * g.v[k])) / g.v[k];  // ~ 2 pi r^2 G
    }
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXd b(J);
      for (std::size_t j = 0; j < J; ++j) b(j) = 2 * std::numbers::pi * radii.r[j] * radii.r[j] * ref.R[c][j];
      // Least squares with the negative weights removed until none is left (active set).
      std::vector<bool> on(n, true);
      Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
      for (int iter = 0; iter < n; ++iter) {
        std::vector<int> cols;
        for (int k = 0; k < n; ++k)
          if (on[k]) cols.push_back(k);
        if (cols.empty()) break;
        Eigen::MatrixXd Asub(J, cols.size());
        for (std::size_t k = 0; k < cols.size(); ++k) Asub.col(k) = A.col(cols[k]);
        const Eigen::VectorXd sol = Asub.colPivHouseholderQr().solve(b);
        x.setZero();
        bool negative = false;
        for (std::size_t k = 0; k < cols.size(); ++k) {
          x(cols[k]) = sol(k);
          if (sol(k) < 0) { on[cols[k]] = false; negative = true; }
        }
        if (!negative) break;
        for (int k = 0; k < n; ++k) x(k) = std::max(x(k), 0.0);
      }
      g.w[c].resize(n);
      // Scaled to integrate to R_d, so that the colour is ours (the fit is of the shape).
      double total = 0;
      for (int k = 0; k < n; ++k) total += std::max(x(k), 0.0);
      for (int k = 0; k < n; ++k) g.w[c][k] = total > 0 ? std::max(x(k), 0.0) * ref.R_d[c] / total : 0.0;
      g.R[c].assign(J, 0.0);
      for (std::size_t j = 0; j < J; ++j)
        for (int k = 0; k < n; ++k) {
          const double v = g.v[k], r = radii.r[j];
          g.R[c][j] += g.w[c][k] * std::exp(-r * r / (2 * v)) / (2 * std::numbers::pi * v);
        }
      g.error += detail::relative_l1(radii, g.R[c], ref.R[c]);
    }
    return g;
  };
  Gaussians best;
  best.error = 1e300;
  for (double lv0 = -15.0; lv0 <= -1.0; lv0 += 0.5)
    for (double lq = 0.6; lq <= 3.0; lq += 0.3) {
      Gaussians g = fit_ladder(std::exp(lv0), std::exp(lq));
      if (g.error < best.error) best = std::move(g);
    }
  return best;
}

Export export_realtime(const Reference& ref, const Options& o, Unit unit) {
  const Gaussians g = fit_gaussians(ref, o.gaussians);
  Rgb R_d_t;
  for (int c = 0; c < 3; ++c)
    for (double w : g.w[c]) R_d_t[c] += w;
  const double scale = per_mm(unit) * o.world_scale;
  Export e;
  e.report = base_report("realtime",
                         "sum of Gaussians with shared variances (d'Eon et al. 2007) and a "
                         "separable screen-space kernel (Jimenez et al. 2015)",
                         unit, ref, R_d_t, g.R);
  json j;
  j["format"] = "Spectral Skin export: real-time subsurface kernels";
  j["name"] = json_text(o.name, kName);
  j["color_space"] = "linear Rec.709 (sRGB primaries, D65)";
  j["units"] = {{"variance", std::string(unit_name(unit)) + "^2"},
                {"offset", std::string(unit_name(unit))}};
  j["R_d"] = vec(ref.R_d);
  json gs = json::array();
  for (int k = 0; k < o.gaussians; ++k)
    gs.push_back({{"variance", g.v[k] * scale * scale},
                  {"weight", {g.w[0][k], g.w[1][k], g.w[2][k]}}});
  j["gaussians"] = gs;
  j["gaussian_definition"] =
      "R(r) = sum_k weight_k exp(-r^2 / (2 variance_k)) / (2 pi variance_k); the weights sum to "
      "R_d per channel";
  // Separable kernel: taps x_i = range sign(t) t^2 over t evenly in [-1, 1], range = 3 sigma of
  // the widest Gaussian; weights = the 1-D marginal of the Gaussian sum times each tap's
  // interval, normalised to 1 per channel (the albedo multiplies separately).
  const double v_max = *std::max_element(g.v.begin(), g.v.end());
  const double range = 3.0 * std::sqrt(v_max);
  const int N = o.taps;
  std::vector<double> x(N);
  for (int i = 0; i < N; ++i) {
    const double t = -1.0 + 2.0 * i / (N - 1);
    x[i] = range * (t < 0 ? -1 : 1) * t * t;
  }
  std::array<std::vector<double>, 3> w;
  for (int c = 0; c < 3; ++c) {
    w[c].resize(N);
    double sum = 0;
    for (int i = 0; i < N; ++i) {
      const double lo = i == 0 ? x[0] : 0.5 * (x[i - 1] + x[i]);
      const double hi = i == N - 1 ? x[N - 1] : 0.5 * (x[i] + x[i + 1]);
      double marginal = 0;
      for (int k = 0; k < o.gaussians; ++k)
        marginal += g.w[c][k] * std::exp(-x[i] * x[i] / (2 * g.v[k])) / std::sqrt(2 * std::numbers::pi * g.v[k]);
      w[c][i] = marginal * std::max(hi - lo, 1e-12);
      sum += w[c][i];
    }
    for (double& v : w[c]) v = sum > 0 ? v / sum : 0.0;
  }
  json taps = json::array();
  for (int i = 0; i < N; ++i)
    taps.push_back({{"offset", x[i] * scale}, {"weight", {w[0][i], w[1][i], w[2][i]}}});
  j["separable_kernel"] = {{"taps", taps},
                           {"definition", "apply horizontally then vertically in screen space "
                                          "with offsets scaled by the pixels per unit at the "
                                          "surface; weights sum to 1 per channel"}};
  e.report.values = {{"variances", [&] {
                        std::vector<double> v;
                        for (double x2 : g.v) v.push_back(x2 * scale * scale);
                        return v;
                      }()}};
  e.files.push_back({"", rounded(j).dump(2) + "\n", false});
  return e;
}

Export export_profile(const Reference& ref, const Options& o, Unit unit) {
  const double scale = per_mm(unit) * o.world_scale;
  Export e;
  e.report = base_report("profile", "the profile itself (no target model)", unit, ref, ref.R_d, ref.R);
  // A table on the reference grid (logarithmic), values per unit^2.
  const std::size_t J = ref.radii.size();
  std::array<double, 3> check{};
  for (int c = 0; c < 3; ++c) check[c] = detail::area_integral(ref.radii, ref.R[c]);
  std::ostringstream csv;
  const std::string u(unit_name(unit));
  csv << "# Spectral Skin radial profile R(r) per linear Rec.709 channel (docs/export.md).\n"
      << "# units: r in " << u << ", R in 1/" << u << "^2; normalisation 2 pi int R(r) r dr = R_d\n"
      << "# R_d: " << triple(ref.R_d, ",") << "\n"
      << "# table_integral: " << num(check[0]) << "," << num(check[1]) << "," << num(check[2]) << "\n";
  csv << "r_" << u << ",R_r,R_g,R_b\n";
  json j;
  j["format"] = "Spectral Skin radial profile";
  j["name"] = json_text(o.name, kName);
  j["color_space"] = "linear Rec.709 (sRGB primaries, D65)";
  j["units"] = {{"r", u}, {"R", "1/" + u + "^2"}};
  j["R_d"] = vec(ref.R_d);
  j["normalisation"] = {{"definition", "2 pi int R(r) r dr = R_d"},
                        {"table_integral", {check[0], check[1], check[2]}}};
  std::vector<double> r(J);
  std::array<std::vector<double>, 3> R;
  image::Planes planes{static_cast<int>(J), 1, {"r", "R", "G", "B"}, {}};
  planes.values.assign(4, std::vector<float>(J));
  for (std::size_t i = 0; i < J; ++i) {
    r[i] = ref.radii.r[i] * scale;
    csv << num(r[i]);
    planes.values[0][i] = static_cast<float>(r[i]);
    for (int c = 0; c < 3; ++c) {
      const double v = ref.R[c][i] / (scale * scale);
      R[c].push_back(v);
      csv << "," << num(v);
      planes.values[1 + c][i] = static_cast<float>(v);
    }
    csv << "\n";
  }
  j["r"] = r;
  j["R"] = {{"r", R[0]}, {"g", R[1]}, {"b", R[2]}};
  e.files.push_back({"", csv.str(), false});
  e.files.push_back({".json", rounded(j).dump(1) + "\n", false});
  ImageFile exr{".exr", std::move(planes), {}, false};
  e.images.push_back(std::move(exr));
  for (int c = 0; c < 3; ++c)
    if (std::abs(check[c] / ref.R_d[c] - 1.0) > 0.01)
      e.report.notes.push_back("the table integrates to R_d only within " +
                               num(100 * std::abs(check[c] / ref.R_d[c] - 1.0)) + " % in channel " +
                               "RGB"[c]);
  return e;
}

}  // namespace

std::string fit_report_json(const FitReport& r, const SkinParameters& p, std::string_view solver,
                            const std::vector<std::string>& files) {
  // Numbers as the files write them (rounded; errors rounded_error); the parameters as given.
  auto rgb = [](const Rgb& c) { return rounded(json{{"r", c.r}, {"g", c.g}, {"b", c.b}}); };
  auto arr = [](const std::array<double, 3>& a) {
    return rounded(json{{"r", a[0]}, {"g", a[1]}, {"b", a[2]}});
  };
  auto err = [](const std::array<double, 3>& a) {
    return json{{"r", rounded_error(a[0])}, {"g", rounded_error(a[1])}, {"b", rounded_error(a[2])}};
  };
  json j;
  j["target"] = r.target;
  j["target_model"] = r.target_model;
  json params = json::object();
  for (const ParameterInfo& info : parameter_table()) params[std::string(info.key)] = p.*(info.member);
  j["parameters"] = params;
  j["solver"] = solver;
  j["units"] = {{"files", std::string(unit_name(r.unit))},
                {"mean_radius_mm", "mm"},
                {"colors", "linear Rec.709 (sRGB primaries, D65)"}};
  json names = json::array();
  for (const std::string& f : files) names.push_back(json_text(f, kOutput));
  j["files"] = names;
  j["representable"] = r.representable;
  j["notes"] = r.notes;
  j["R_d_ours"] = rgb(r.R_d_ours);
  j["R_d_target"] = rgb(r.R_d_target);
  j["delta_e_2000"] = rounded_error(r.delta_e_2000);
  j["profile_l1"] = err(r.profile_l1);
  j["mean_radius_mm"] = arr(r.mean_radius_mm);
  j["mean_radius_error"] = err(r.mean_radius_error);
  j["values"] = rounded(report_values_json(r));
  if (r.texels) {
    j["texels"] = r.texels;
    j["max_delta_e_2000"] = rounded_error(r.max_delta_e_2000);
  }
  return j.dump(2) + "\n";
}

namespace {

Options checked(const Options& in) {
  Options o = in;
  if (o.stem.empty()) o.stem = o.name;
  o.validate();
  return o;
}

Export run(const Target& target, const Reference& ref, const Options& o, const MapsFit* mf) {
  const Unit unit = o.unit.value_or(target.default_unit);
  const std::string_view n = target.name;
  Export e;
  if (n == "openpbr" || n == "standard-surface") e = export_materialx(n == "openpbr", ref, o, unit, mf);
  else if (n == "cycles") e = export_cycles(ref, o, unit, mf);
  else if (n == "unreal") e = export_unreal(ref, o, unit);
  else if (n == "unity") e = export_unity(ref, o, unit);
  else if (n == "pbrt-v4") e = export_pbrt(ref, o, unit);
  else if (n == "mitsuba3") e = export_mitsuba(ref, o, unit);
  else if (n == "realtime") e = export_realtime(ref, o, unit);
  else e = export_profile(ref, o, unit);
  return e;
}

}  // namespace

struct Prepared {
  Reference ref;
};

void require_textures(const Target& target) {
  if (target.takes_textures) return;
  std::string which;
  for (const Target& t : targets())
    if (t.takes_textures) which += (which.empty() ? "" : ", ") + std::string(t.name);
  throw InputError("parameter-maps: target " + std::string(target.name) +
                   " takes no textures (its profile is one per material); targets that do: " +
                   which);
}

std::shared_ptr<const Prepared> prepare(const SkinParameters& parameters,
                                        const transport::Model& model) {
  parameters.validate();
  ProfileSolver solver(detail::reference_radii());
  return std::make_shared<const Prepared>(Prepared{detail::make_reference(parameters, model, solver)});
}

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
  if (!maps) return run(target, prepare(parameters, model)->ref, o, nullptr);
  require_textures(target);
  // The single-material values are those of the maps' mean texel.
  SkinParameters p = parameters;
  const MapsFit mf = fit_maps(target.name, parameters, model, *maps, progress);
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
