// MaterialX targets: OpenPBR Surface (openpbr) and Autodesk Standard Surface
// (standard-surface), both a random walk whose albedo is inverted by Chiang et al. 2016 eq. 3
// (docs/export.md, "The random-walk targets").
#include <algorithm>
#include <sstream>

#include "fits.hpp"
#include "report.hpp"
#include "skin/util/escape.hpp"

namespace skin::exporting::detail {

using skin::util::Rgb;

using skin::physics::SkinParameters;

namespace {

// The two schemas take the same inputs under their own names; the radius is a scalar (with the
// distance unit) times a colour in both, in opposite roles (OpenPBR: subsurface_radius is the
// scalar, Standard Surface: subsurface_scale is).
struct Schema {
  const char *label, *version;  // in the report; MaterialX version
  const char *node, *base, *specular, *ior, *subsurface, *anisotropy, *radius_scalar,
      *radius_colour;
  bool scalar_first;
};
constexpr Schema kOpenPbr = {"OpenPBR", "1.39", "open_pbr_surface", "base_weight",
                             "specular_weight", "specular_ior", "subsurface_weight",
                             "subsurface_scatter_anisotropy", "subsurface_radius",
                             "subsurface_radius_scale", true};
constexpr Schema kStandardSurface = {"Standard Surface", "1.38", "standard_surface", "base",
                                     "specular", "specular_IOR", "subsurface",
                                     "subsurface_anisotropy", "subsurface_scale",
                                     "subsurface_radius", false};

double chiang(double A) { return chiang_alpha(A); }

TexelFit texel(const Reference& ref) { return walk_texel(ref, fit_walk(ref, chiang, 1.0), 1.0); }

Export write(const Context& ctx, const Schema& s) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  const MapsFit* mf = ctx.maps;
  const WalkFit w = fit_walk(ref, chiang, 1.0);
  Export e;
  const double scale = ctx.scale();
  const Rgb d = {w.d_mm.r * scale, w.d_mm.g * scale, w.d_mm.b * scale};
  const double d_max = std::max({d.r, d.g, d.b});
  const Rgb d_rel = {d.r / d_max, d.g / d_max, d.b / d_max};
  const SkinParameters& p = ref.parameters;
  e.report = fit_report(ctx,
                        std::string(s.label) +
                            " random-walk subsurface: radius = extinction mean free path, colour = "
                            "multiple-scattering albedo inverted by Chiang et al. 2016 eq. 3, "
                            "isotropic walk, index-matched boundary",
                        w.R_d, w.R);
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
  const std::string material = util::escape::xml_attribute(o.name, kName);
  const std::string shader = material + "_surface";
  x << "<?xml version=\"1.0\"?>\n";
  x << "<materialx version=\"" << s.version << "\" colorspace=\"lin_rec709\">\n";
  x << "  <!--\n" << header_lines("   ", e, ctx) << "  -->\n";
  const std::string u = std::string(unit_long_name(unit));
  auto input = [&](const std::string& name, const std::string& type, const std::string& value,
                   const std::string& extra = "") {
    x << "    <input name=\"" << name << "\" type=\"" << type << "\" value=\"" << value << "\""
      << extra << " />\n";
  };
  if (mf) {
    x << "  <image name=\"" << material << "_subsurface_color_map\" type=\"color3\">\n"
      << "    <input name=\"file\" type=\"filename\" value=\""
      << util::escape::xml_attribute(o.stem + ".subsurface_color.png", kOutput)
      << "\" colorspace=\"srgb_texture\" />\n  </image>\n";
    x << "  <image name=\"" << material << "_subsurface_radius_map\" type=\"color3\">\n"
      << "    <!-- linear data in " << u << " (no colour space) -->\n"
      << "    <input name=\"file\" type=\"filename\" value=\""
      << util::escape::xml_attribute(o.stem + ".subsurface_radius.exr", kOutput) << "\" />\n  </image>\n";
  }
  const std::string dist = " unittype=\"distance\" unit=\"" + u + "\"";
  auto connect = [&](const std::string& name, const std::string& type, const std::string& node) {
    x << "    <input name=\"" << name << "\" type=\"" << type << "\" nodename=\"" << node
      << "\" />\n";
  };
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

Export write_openpbr(const Context& ctx) { return write(ctx, kOpenPbr); }
Export write_standard_surface(const Context& ctx) { return write(ctx, kStandardSurface); }

}  // namespace

TargetSpec openpbr_target() {
  return {"openpbr", "MaterialX document with an OpenPBR Surface (open_pbr_surface)", ".mtlx",
          Unit::m, write_openpbr, texel};
}

TargetSpec standard_surface_target() {
  return {"standard-surface", "MaterialX document with an Autodesk Standard Surface", ".mtlx",
          Unit::m, write_standard_surface, texel};
}

}  // namespace skin::exporting::detail
