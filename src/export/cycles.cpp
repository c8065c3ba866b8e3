// Cycles (Blender 3.x, 4.x): a Python script making a Principled BSDF material whose random walk
// (Cycles' own albedo remap) reproduces the skin (docs/export.md, "The random-walk targets").
#include <numbers>
#include <sstream>

#include "fits.hpp"
#include "report.hpp"
#include "skin/util/escape.hpp"

namespace skin::exporting::detail {

using skin::util::Rgb;


using skin::physics::SkinParameters;


namespace {

double cycles_g0(double A) { return cycles_alpha(A, 0.0); }

// Cycles 3.x adds a retro-reflection lobe to the Principled BSDF's subsurface closure (the
// Disney diffuse retro-reflection, f = A / pi RR F_L, RR = 2 r cos^2 theta_d, F_L = (1 - cos
// theta_l)^5). Under uniform white light and seen along the normal it adds
// 2 r int_0^1 (1 + mu) (1 - mu)^5 mu dmu = (5 / 84) r of A (r: Principled roughness).
double cycles_retro_gain(double principled_roughness) {
  return 1.0 + 5.0 / 84.0 * principled_roughness;
}

// The walk fit of Cycles' Principled BSDF at this skin's roughness.
WalkFit fit(const Reference& ref) {
  return fit_walk(ref, cycles_g0, cycles_retro_gain(perceptual_roughness(ref.parameters)));
}

// Cycles' radius is 4 pi times the mean free path (see write).
TexelFit texel(const Reference& ref) {
  return walk_texel(ref, fit(ref), 4.0 * std::numbers::pi);
}

Export write(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  const MapsFit* mf = ctx.maps;
  const SkinParameters& p = ref.parameters;
  const double rough = perceptual_roughness(p);
  const WalkFit w = fit(ref);
  const double scale = ctx.scale();
  // Cycles' Random Walk (Fixed Radius) in 3.x, Random Walk in 4.x, scale the radius by 1 / (4 pi)
  // to get the mean free path (bssrdf_setup_radius): radius = 4 pi d.
  const double four_pi = 4.0 * std::numbers::pi;
  const Rgb radius = {four_pi * w.d_mm.r * scale, four_pi * w.d_mm.g * scale,
                      four_pi * w.d_mm.b * scale};
  Export e;
  e.report = fit_report(
      ctx,
      "Cycles random walk (3.x 'Random Walk (Fixed Radius)', 4.x 'Random Walk'): mean free path = "
      "radius / (4 pi), albedo through Cycles' remap at anisotropy 0, cosine-weighted entry, "
      "index-matched walk; 3.x adds the Principled retro-reflection lobe ((5/84) roughness of the "
      "albedo at normal view)",
      w.R_d, w.R);
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
  s << header_lines("#", e, ctx);
  s << "# Run: blender --background --python THIS_FILE [-- --blend OUT.blend], or from Blender's\n"
       "# text editor. Creates (or updates) the material NAME and returns it from make_material().\n"
       "import os\nimport sys\n\nimport bpy\n\n";
  s << "NAME = " << util::escape::python_string(o.name, kName) << "\n";
  s << "SUBSURFACE_COLOR = (" << triple(w.A) << ")  # linear Rec.709\n";
  s << "SUBSURFACE_RADIUS = (" << triple(radius) << ")  # " << unit_name(unit)
    << " (Blender units): 4 pi x mean free path\n";
  s << "ROUGHNESS = " << num(rough) << "\n";
  s << "IOR = " << num(p.eta) << "\n";
  s << "SPECULAR = " << num(specular_3x) << "  # 3.x: F0 / 0.08 x oiliness\n";
  s << "SPECULAR_IOR_LEVEL = " << num(0.5 * p.oiliness) << "  # 4.x: 0.5 = the IOR's own F0\n";
  if (mf)
    s << "COLOR_MAP = " << util::escape::python_string(o.stem + ".subsurface_color.png", kOutput)
      << "  # sRGB\n"
      << "RADIUS_MAP = " << util::escape::python_string(o.stem + ".subsurface_radius.exr", kOutput)
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

}  // namespace

TargetSpec cycles_target() {
  return {"cycles", "Python script for Blender (3.x, 4.x) making a Principled BSDF material", ".py",
          Unit::m, write, texel};
}

}  // namespace skin::exporting::detail
