// Scene files (docs/scene-format.md) and the built-in default scene as SceneDescriptions, their
// edits (the CLI's flags), and the built Scene handle.
#include "skin/render/scene.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <nlohmann/json.hpp>
#include <map>
#include <set>
#include <sstream>

#include "scene_impl.hpp"
#include "skin/color/color.hpp"
#include "skin/util/error.hpp"
#include "skin/util/input_file.hpp"

namespace skin::render {

using skin::util::InputError;
using skin::util::format_number;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_parameter;
using skin::physics::find_preset;
using skin::physics::kInfinity;
using skin::physics::parameter_info;
using skin::physics::parameter_table;

using json = nlohmann::json;

namespace {

// Reads one JSON object strictly: every key must be known, every value of the right type; the
// messages name the scene file and the key path.
class Reader {
 public:
  Reader(const json& j, std::string file, std::string where) : j_(j), file_(std::move(file)), where_(std::move(where)) {
    if (!j_.is_object()) fail("must be a JSON object");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("scene = '" + file_ + "': " + (where_.empty() ? "" : where_ + ": ") + what);
  }
  void allow(std::initializer_list<const char*> keys) const {
    const std::set<std::string> ok(keys.begin(), keys.end());
    for (const auto& [k, v] : j_.items())
      if (!ok.count(k)) {
        std::string list;
        for (const auto& o : ok) list += (list.empty() ? "" : ", ") + o;
        fail("unknown key '" + k + "' (known: " + list + ")");
      }
  }
  bool has(const char* k) const { return j_.contains(k); }
  const json& raw(const char* k) const {
    if (!has(k)) fail("missing key '" + std::string(k) + "'");
    return j_.at(k);
  }
  std::string path(const char* k) const { return where_.empty() ? k : where_ + "." + k; }
  double number(const char* k, double def) const {
    if (!has(k)) return def;
    return number(k);
  }
  double number(const char* k) const {
    const json& v = raw(k);
    if (!v.is_number()) fail("'" + std::string(k) + "' must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail("'" + std::string(k) + "' must be finite");
    return x;
  }
  int integer(const char* k, int def) const {
    if (!has(k)) return def;
    const json& v = raw(k);
    if (!v.is_number_integer()) fail("'" + std::string(k) + "' must be an integer");
    return v.get<int>();
  }
  bool boolean(const char* k, bool def) const {
    if (!has(k)) return def;
    const json& v = raw(k);
    if (!v.is_boolean()) fail("'" + std::string(k) + "' must be true or false");
    return v.get<bool>();
  }
  std::string string(const char* k) const {
    const json& v = raw(k);
    if (!v.is_string()) fail("'" + std::string(k) + "' must be a string");
    return v.get<std::string>();
  }
  Vec3 vec3(const char* k) const {
    const json& v = raw(k);
    if (!v.is_array() || v.size() != 3) fail("'" + std::string(k) + "' must be an array of 3 numbers");
    Vec3 r;
    for (int i = 0; i < 3; ++i) {
      if (!v[static_cast<std::size_t>(i)].is_number()) fail("'" + std::string(k) + "' must be an array of 3 numbers");
      (i == 0 ? r.x : i == 1 ? r.y : r.z) = v[static_cast<std::size_t>(i)].get<double>();
    }
    return r;
  }
  Vec3 vec3(const char* k, Vec3 def) const { return has(k) ? vec3(k) : def; }
  // A colour: one number (grey) or [r, g, b], each >= 0.
  Rgb3 rgb(const char* k, Rgb3 def) const {
    if (!has(k)) return def;
    const json& v = raw(k);
    Rgb3 c;
    if (v.is_number()) c = Rgb3{1, 1, 1} * v.get<double>();
    else if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number())
      c = {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    else fail("'" + std::string(k) + "' must be a number or an array [r, g, b]");
    for (int i = 0; i < 3; ++i)
      if (!(c[i] >= 0) || !std::isfinite(c[i])) fail("'" + std::string(k) + "' must be finite and >= 0");
    return c;
  }
  const json& j() const { return j_; }
  const std::string& file() const { return file_; }

 private:
  const json& j_;
  std::string file_, where_;
};

std::string resolve(const std::string& base_dir, const std::string& p) {
  const std::filesystem::path q(p);
  return (q.is_absolute() || base_dir.empty()) ? p : (std::filesystem::path(base_dir) / q).lexically_normal().string();
}

// Rethrows an InputError from a loader with the scene file in front.
template <class F>
auto with_context(const std::string& file, const std::string& where, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError("scene = '" + file + "': " + where + ": " + e.what());
  }
}

// The material's `solver`: a transport model of the registry by name.
const transport::Model* read_solver(const Reader& r) {
  return with_context(r.file(), r.path("solver"), [&] { return &transport::find_model(r.string("solver")); });
}

MaterialDescription parse_material(const Reader& r, const std::string& name, const std::string& base) {
  MaterialDescription m;
  m.name = name;
  const std::string type = r.string("type");
  if (type == "diffuse") {
    r.allow({"type", "albedo", "albedo_texture"});
    m.kind = MaterialKind::diffuse;
    m.albedo = r.rgb("albedo", {0.5, 0.5, 0.5});
    if (r.has("albedo_texture"))
      m.albedo_map = with_context(r.file(), r.path("albedo_texture"), [&] { return load_texture(resolve(base, r.string("albedo_texture")), true); });
  } else if (type == "skin") {
    SkinParameters p = r.has("preset") ? with_context(r.file(), r.path("preset"), [&] { return find_preset(r.string("preset")).parameters; })
                                       : SkinParameters{};
    // Every parameter of the table by its key or the paper's symbol (skin::physics::parameter_table()).
    static const std::set<std::string> other = {"type", "preset", "albedo_texture", "texture_reference",
                                                "parameter_maps", "solver"};
    std::set<const ParameterInfo*> given;
    for (const auto& [k, v] : r.j().items()) {
      if (other.count(k) != 0) continue;
      const ParameterInfo* info = find_parameter(k);
      if (info == nullptr) {
        std::string known;
        for (const auto& o : other) known += o + ", ";
        for (const auto& row : parameter_table()) known += std::string(row.key) + ", ";
        r.fail("unknown key '" + k + "' (known: " + known + "or the paper's symbols C_m, beta_m, C_h, rho_s, gamma)");
      }
      if (!given.insert(info).second) r.fail("'" + k + "' sets " + std::string(info->key) + " a second time");
      p.*(info->member) = r.number(k.c_str());
    }
    if (r.has("solver")) m.solver = read_solver(r);
    if (r.has("parameter_maps")) {
      const Reader pm(r.raw("parameter_maps"), r.file(), r.path("parameter_maps"));
      for (const auto& [k, v] : pm.j().items()) {
        const ParameterInfo* info =
            with_context(r.file(), pm.path(k.c_str()), [&key = k] { return &parameter_info(key, "parameter"); });
        const Reader e(v, r.file(), pm.path(k.c_str()));
        e.allow({"texture", "channel", "min", "max", "levels"});
        ParameterMap mp;
        mp.key = std::string(info->key);
        mp.member = info->member;
        mp.levels = e.integer("levels", 4);
        if (mp.levels < 2 || mp.levels > 16) e.fail("'levels' = " + std::to_string(mp.levels) + " is out of range: [2, 16]");
        if (e.has("min") != e.has("max")) e.fail("give both 'min' and 'max' (texels 0-1 scaled to them) or neither (texels are values)");
        const std::string file = resolve(base, e.string("texture"));
        const std::string channel = e.has("channel") ? e.string("channel") : std::string();
        mp.texture = with_context(r.file(), e.path("texture"), [&] { return load_map_texture(file, channel, mp.key); });
        if (e.has("min")) {
          mp.min = e.number("min");
          mp.max = e.number("max");
          if (!(mp.max > mp.min)) e.fail("'max' = " + format_number(mp.max) + " must be > 'min' = " + format_number(mp.min));
        } else {
          // The channel holds the parameter's values: the nodes span what the texture holds.
          mp.values = true;
          double lo = std::numeric_limits<double>::infinity(), hi = -lo;
          for (std::size_t i = 0; i < mp.texture->rgb.size(); i += 3) {
            const double x = mp.texture->rgb[i];
            if (!info->in_range(x))
              e.fail("texture '" + file + "' holds " + info->label() + " = " + format_number(x) +
                     ", outside its range " + info->range_text());
            lo = std::min(lo, x);
            hi = std::max(hi, x);
          }
          if (!(hi > lo)) {  // one value everywhere: a constant, no map
            p.*(info->member) = lo;
            continue;
          }
          mp.min = lo;
          mp.max = hi;
        }
        m.maps.push_back(mp);
      }
    }
    m.kind = MaterialKind::skin;
    with_context(r.file(), "materials." + name, [&] { p.validate(); return 0; });
    m.parameters = p;
    if (r.has("albedo_texture")) {
      m.albedo_map = with_context(r.file(), r.path("albedo_texture"), [&] { return load_texture(resolve(base, r.string("albedo_texture")), true); });
      // The chromophores assumed to have produced the texture (DJ06 section 3.6): the texture
      // is divided by their R_d colour. Default: the material's own parameters.
      if (r.has("texture_reference")) {
        m.texture_reference = with_context(r.file(), r.path("texture_reference"), [&] { return find_preset(r.string("texture_reference")).parameters; });
      }
    } else if (r.has("texture_reference")) {
      r.fail("'texture_reference' needs 'albedo_texture'");
    }
    if (r.has("parameter_maps")) {
      const Reader pm(r.raw("parameter_maps"), r.file(), r.path("parameter_maps"));
      std::size_t nodes = 1;
      for (const auto& mp : m.maps) nodes *= static_cast<std::size_t>(mp.levels);
      if (nodes > 64) pm.fail("the maps need " + std::to_string(nodes) + " precomputed parameter sets; at most 64 (lower 'levels')");
    }
  } else if (type == "layered") {
    r.allow({"type", "layers", "eta_above", "eta_below", "rho_s", "roughness", "eta", "albedo_texture",
             "solver"});
    m.kind = MaterialKind::layered;
    if (r.has("solver")) m.solver = read_solver(r);
    m.rho_s = r.number("rho_s", 0.0);
    m.roughness = r.number("roughness", 0.35);
    m.eta = r.number("eta", 1.4);
    if (m.rho_s < 0 || m.rho_s > 1) r.fail("'rho_s' = " + format_number(m.rho_s) + " is out of range: [0, 1]");
    if (!(m.roughness > 0)) r.fail("'roughness' must be > 0");
    const json& layers = r.raw("layers");
    if (!layers.is_array() || layers.empty()) r.fail("'layers' must be a non-empty array");
    std::array<LayerStack, 3> stacks;
    for (auto& s : stacks) {
      s.eta_above = r.number("eta_above", 1.0);
      s.eta_below = r.number("eta_below", 1.0);
    }
    for (std::size_t i = 0; i < layers.size(); ++i) {
      const Reader lr(layers[i], r.file(), r.path("layers") + "[" + std::to_string(i) + "]");
      lr.allow({"sigma_a", "sigma_s_prime", "thickness_mm", "thickness", "eta", "g"});
      if (lr.has("thickness_mm") && lr.has("thickness")) lr.fail("give 'thickness_mm' or 'thickness', not both");
      const char* thickness_key = lr.has("thickness_mm") ? "thickness_mm" : "thickness";
      const Rgb3 sa = lr.rgb("sigma_a", {}), ss = lr.rgb("sigma_s_prime", {1, 1, 1});
      double thickness = kInfinity;
      if (lr.has(thickness_key) && !lr.raw(thickness_key).is_null()) thickness = lr.number(thickness_key);
      for (int c = 0; c < 3; ++c) {
        Layer l;
        l.sigma_a = sa[c];
        l.sigma_s_prime = ss[c];
        l.thickness = thickness;
        l.eta = lr.number("eta", 1.4);
        l.g = lr.number("g", 0.9);
        stacks[static_cast<std::size_t>(c)].layers.push_back(l);
      }
    }
    m.stacks = stacks;
    if (r.has("albedo_texture"))
      m.albedo_map = with_context(r.file(), r.path("albedo_texture"), [&] { return load_texture(resolve(base, r.string("albedo_texture")), true); });
  } else {
    r.fail("unknown material type '" + type + "' (known: diffuse, skin, layered)");
  }
  return m;
}

void apply_transform(const Reader& r, std::vector<Mesh>& meshes) {
  if (!r.has("transform")) return;
  const Reader t(r.raw("transform"), r.file(), r.path("transform"));
  t.allow({"scale", "rotate_y", "translate"});
  const double s = t.number("scale", 1.0);
  if (!(s > 0)) t.fail("'scale' must be > 0");
  const double a = t.number("rotate_y", 0.0) * kPi / 180;
  const Vec3 tr = t.vec3("translate", {});
  const double c = std::cos(a), sn = std::sin(a);
  for (auto& m : meshes) {
    for (auto& p : m.position) p = Vec3{c * p.x + sn * p.z, p.y, -sn * p.x + c * p.z} * s + tr;
    for (auto& n : m.normal) n = Vec3{c * n.x + sn * n.z, n.y, -sn * n.x + c * n.z};
  }
}

SceneDescription::Data parse_scene(const json& root, const std::string& file, const std::string& base) {
  const Reader r(root, file, "");
  r.allow({"unit_mm", "camera", "render", "materials", "objects", "lights", "environment", "description"});
  SceneDescription::Data s;
  s.source = file;
  s.mm_per_unit = r.number("unit_mm", 1.0);
  if (!(s.mm_per_unit > 0)) r.fail("'unit_mm' must be > 0");
  {
    const Reader c(r.raw("camera"), file, "camera");
    c.allow({"eye", "look_at", "up", "fov", "resolution"});
    s.camera.eye = c.vec3("eye");
    s.camera.target = c.vec3("look_at");
    s.camera.up = c.vec3("up", {0, 1, 0});
    s.camera.fov_deg = c.number("fov", 40);
    if (!(s.camera.fov_deg > 0 && s.camera.fov_deg < 180)) c.fail("'fov' = " + format_number(s.camera.fov_deg) + " is out of range: (0, 180) degrees");
    if (length(cross(s.camera.target - s.camera.eye, s.camera.up)) == 0) c.fail("'up' is parallel to the view direction (or eye == look_at)");
    if (c.has("resolution")) {
      const json& res = c.raw("resolution");
      if (!res.is_array() || res.size() != 2 || !res[0].is_number_integer() || !res[1].is_number_integer())
        c.fail("'resolution' must be [width, height]");
      s.camera.width = res[0].get<int>();
      s.camera.height = res[1].get<int>();
      if (s.camera.width < 1 || s.camera.height < 1 || s.camera.width > 16384 || s.camera.height > 16384)
        c.fail("'resolution' out of range: each side in [1, 16384]");
    }
  }
  if (r.has("render")) {
    const Reader q(r.raw("render"), file, "render");
    q.allow({"spp", "max_depth", "exposure", "tone_map", "spectral", "subsurface", "point_spacing",
             "point_solid_angle"});
    s.spp = q.integer("spp", s.spp);
    s.spectral = q.boolean("spectral", false);
    s.max_depth = q.integer("max_depth", s.max_depth);
    s.exposure = q.number("exposure", 0.0);
    if (q.has("tone_map"))
      s.tone_map = with_context(file, q.path("tone_map"), [&] { return image::tone_map_from_name(q.string("tone_map")); });
    if (s.spp < 1) q.fail("'spp' must be >= 1");
    if (s.max_depth < 0 || s.max_depth > 1000) q.fail("'max_depth' must be in [0, 1000]");
    if (q.has("subsurface")) {
      const std::string v = q.string("subsurface");
      if (v != "probes" && v != "points") q.fail("'subsurface' = '" + v + "' is not allowed: probes or points");
      s.subsurface_points = v == "points";
    }
    s.point_spacing = q.number("point_spacing", s.point_spacing);
    s.point_solid_angle = q.number("point_solid_angle", s.point_solid_angle);
    if (!(s.point_spacing > 0)) q.fail("'point_spacing' = " + format_number(s.point_spacing) + " is out of range: must be > 0 mm");
    if (!(s.point_solid_angle >= 0)) q.fail("'point_solid_angle' = " + format_number(s.point_solid_angle) + " is out of range: must be >= 0 sr");
  }
  std::map<std::string, std::size_t> mat_index;
  {
    const json& mats = r.raw("materials");
    if (!mats.is_object() || mats.empty()) r.fail("'materials' must be a non-empty object of named materials");
    for (const auto& [name, mj] : mats.items()) {
      const Reader mr(mj, file, "materials." + name);
      mat_index[name] = s.materials.size();
      s.materials.push_back(parse_material(mr, name, base));
    }
  }
  const json& objs = r.raw("objects");
  if (!objs.is_array() || objs.empty()) r.fail("'objects' must be a non-empty array");
  for (std::size_t i = 0; i < objs.size(); ++i) {
    const Reader o(objs[i], file, "objects[" + std::to_string(i) + "]");
    o.allow({"mesh", "sphere", "quad", "material", "transform", "flip_v"});
    const std::string mname = o.string("material");
    const auto it = mat_index.find(mname);
    if (it == mat_index.end()) o.fail("unknown material '" + mname + "'");
    std::vector<Mesh> meshes;
    const int shapes = int(o.has("mesh")) + int(o.has("sphere")) + int(o.has("quad"));
    if (shapes != 1) o.fail("needs exactly one of 'mesh', 'sphere', 'quad'");
    if (o.has("mesh")) {
      const std::string p = resolve(base, o.string("mesh"));
      meshes = with_context(file, o.path("mesh"), [&] { return load_mesh_file(p, it->second); });
      if (o.boolean("flip_v", false))
        for (auto& m : meshes)
          for (auto& uv : m.uv) uv.y = 1 - uv.y;
    } else if (o.has("sphere")) {
      const Reader sp(o.raw("sphere"), file, o.path("sphere"));
      sp.allow({"center", "radius"});
      const double rad = sp.number("radius");
      if (!(rad > 0)) sp.fail("'radius' must be > 0");
      meshes.push_back(make_sphere(sp.vec3("center"), rad, 64, 128, it->second));
    } else {
      const Reader q(o.raw("quad"), file, o.path("quad"));
      q.allow({"corner", "edge_u", "edge_v"});
      meshes.push_back(make_quad(q.vec3("corner"), q.vec3("edge_u"), q.vec3("edge_v"), it->second));
    }
    apply_transform(o, meshes);
    for (auto& m : meshes) s.meshes.push_back(std::move(m));
  }
  if (r.has("lights")) {
    const json& ls = r.raw("lights");
    if (!ls.is_array()) r.fail("'lights' must be an array");
    for (std::size_t i = 0; i < ls.size(); ++i) {
      const Reader l(ls[i], file, "lights[" + std::to_string(i) + "]");
      const std::string type = l.string("type");
      // The light's value (a number or [r, g, b]) times the colour of the CIE illuminant it
      // names, if any: linear sRGB of luminance 1 on the materials' wavelength grid, D65 = 1, 1, 1
      // (color::Colorimetry::illuminant_rgb).
      const auto value = [&l](const char* key) {
        Rgb3 v = l.rgb(key, {1, 1, 1});
        if (l.has("illuminant")) {
          const std::string name = l.string("illuminant");
          try {
            v *= color::Colorimetry(WavelengthGrid(), color::find_illuminant(name)).illuminant_rgb();
          } catch (const InputError& e) {
            l.fail(e.what());
          }
        }
        return v;
      };
      if (type == "point") {
        l.allow({"type", "position", "intensity", "illuminant"});
        s.lights.emplace_back(PointLight{l.vec3("position"), value("intensity")});
      } else if (type == "directional") {
        l.allow({"type", "direction", "irradiance", "illuminant"});
        s.lights.emplace_back(DirectionalLight{normalize(l.vec3("direction")), value("irradiance")});
      } else if (type == "sphere") {
        l.allow({"type", "center", "radius", "radiance", "illuminant"});
        const SphereLight L{l.vec3("center"), l.number("radius"), value("radiance")};
        if (!(L.radius > 0)) l.fail("'radius' must be > 0");
        s.lights.emplace_back(L);
      } else if (type == "quad") {
        l.allow({"type", "corner", "edge_u", "edge_v", "radiance", "illuminant"});
        const QuadLight L{l.vec3("corner"), l.vec3("edge_u"), l.vec3("edge_v"), value("radiance")};
        if (!(L.area() > 0)) l.fail("'edge_u' and 'edge_v' must span a non-zero area");
        s.lights.emplace_back(L);
      } else {
        l.fail("unknown light type '" + type + "' (known: point, directional, sphere, quad)");
      }
      if (l.has("illuminant")) s.lights.back().set_illuminant(&color::find_illuminant(l.string("illuminant")));
    }
  }
  if (r.has("environment")) {
    const Reader e(r.raw("environment"), file, "environment");
    e.allow({"radiance", "map", "scale", "rotation", "illuminant"});
    s.environment.constant = e.rgb("radiance", {});
    if (e.has("illuminant")) {  // as for lights: the value times the illuminant's colour
      if (e.has("map")) e.fail("'illuminant' needs a constant 'radiance', not a 'map'");
      try {
        s.environment.illuminant = &color::find_illuminant(e.string("illuminant"));
        s.environment.constant *=
            color::Colorimetry(WavelengthGrid(), *s.environment.illuminant).illuminant_rgb();
      } catch (const InputError& x) {
        e.fail(x.what());
      }
    }
    s.environment.scale = e.number("scale", 1.0);
    s.environment.rotation_deg = e.number("rotation", 0.0);
    if (e.has("map")) {
      s.environment.map = with_context(file, e.path("map"), [&] { return load_texture(resolve(base, e.string("map")), true); });
      s.environment.build_distribution();
    }
  }
  if (s.spectral) with_context(file, "render.spectral", [&] { check_spectral(s); return 0; });
  return s;
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const RenderSettings& s) {
  return os << "RenderSettings{spp=" << s.spp << ", seed=" << s.seed << ", threads=" << s.threads
            << ", max_depth=" << s.max_depth << ", time_budget=" << s.time_budget << " s, " << s.width << "x"
            << s.height << ", subsurface="
            << (s.subsurface == RenderSettings::Subsurface::points   ? "points"
                : s.subsurface == RenderSettings::Subsurface::probes ? "probes"
                                                                     : "scene")
            << ", point_spacing=" << s.point_spacing << " mm, point_solid_angle=" << s.point_solid_angle << '}';
}

std::ostream& operator<<(std::ostream& os, const RenderStats& s) {
  return os << "RenderStats{" << s.seconds << " s, spp=" << s.spp_done << ", samples=" << s.camera_samples
            << ", invalid=" << s.invalid_samples << '}';
}

Scene make_scene(SceneData data) { return Scene(std::make_unique<Scene::Impl>(std::move(data))); }

Scene::Scene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;
Scene::~Scene() = default;

Scene Scene::parse(const std::string& text, const std::string& base_dir, const std::string& name) {
  return SceneDescription::parse(text, base_dir, name).build();
}
Scene Scene::load(const std::string& path) { return SceneDescription::load(path).build(); }
Scene Scene::default_scene() { return SceneDescription::default_scene().build(); }

SceneDescription::SceneDescription(std::unique_ptr<Data> d) : d_(std::move(d)) {}
SceneDescription::SceneDescription(const SceneDescription& o) : d_(std::make_unique<Data>(*o.d_)) {}
SceneDescription& SceneDescription::operator=(const SceneDescription& o) {
  if (this != &o) d_ = std::make_unique<Data>(*o.d_);
  return *this;
}
SceneDescription::SceneDescription(SceneDescription&&) noexcept = default;
SceneDescription& SceneDescription::operator=(SceneDescription&&) noexcept = default;
SceneDescription::~SceneDescription() = default;

SceneDescription SceneDescription::parse(const std::string& text, const std::string& base_dir, const std::string& name) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number beyond double
    throw InputError("scene = '" + name + "': malformed JSON: " + e.what());
  }
  return SceneDescription(std::make_unique<Data>(parse_scene(root, name, base_dir)));
}

SceneDescription SceneDescription::load(const std::string& path) {
  return parse(util::io::read_file(path, "scene"), std::filesystem::path(path).parent_path().string(), path);
}

SceneDescription SceneDescription::default_scene() {
  // Scene units are mm. Three Fig. 8 skin types on spheres of radius 28 mm and a thin ear-like
  // fin (4 mm thick, like the rim of an ear) of the Fig. 10 "ear" preset, on a grey floor; a large key light in front,
  // a small back light behind the fin that shows light bleeding through it.
  auto s = std::make_unique<Data>();
  s->source = "built-in default scene";
  s->mm_per_unit = 1.0;
  s->camera = {{0, 70, 330}, {0, 24, 0}, {0, 1, 0}, 30.0, 384, 256};
  s->spp = 64;
  s->max_depth = 4;
  s->exposure = 0.3;
  for (const char* name : {"caucasian", "asian", "african", "ear"}) {
    MaterialDescription m = skin_description(find_preset(name).parameters);
    m.name = name;
    s->materials.push_back(std::move(m));
  }
  MaterialDescription floor;
  floor.name = "floor";
  floor.albedo = {0.35, 0.35, 0.35};
  s->materials.push_back(floor);
  s->meshes.push_back(make_sphere({-96, 28, 0}, 28, 64, 128, 0));
  s->meshes.push_back(make_sphere({-32, 28, 0}, 28, 64, 128, 1));
  s->meshes.push_back(make_sphere({32, 28, 0}, 28, 64, 128, 2));
  s->meshes.push_back(make_ellipsoid({94, 30, 0}, {18, 28, 2}, 64, 128, 3));
  s->meshes.push_back(make_quad({-400, 0, 300}, {800, 0, 0}, {0, 0, -700}, 4));
  s->lights.emplace_back(SphereLight{{-160, 260, 260}, 30, {40, 40, 40}});  // key
  s->lights.emplace_back(SphereLight{{98, 36, -30}, 6, {400, 400, 400}});    // back
  s->environment.constant = {0.04, 0.045, 0.05};
  return SceneDescription(std::move(s));
}

void SceneDescription::set_skin_parameters(const SkinParameters& p) {
  update_skin_parameters([&p](const SkinParameters&) { return p; });
}

void SceneDescription::update_skin_parameters(const std::function<SkinParameters(const SkinParameters&)>& change) {
  for (auto& m : d_->materials)
    if (m.kind == MaterialKind::skin) m.parameters = change(m.parameters);  // mapped ones keep their maps
}

void SceneDescription::set_solver(const transport::Model& solver) {
  for (auto& m : d_->materials)
    if (m.translucent()) m.solver = &solver;
}

void SceneDescription::set_spectral(bool spectral) {
  if (spectral) check_spectral(*d_);
  d_->spectral = spectral;
}

bool SceneDescription::spectral() const { return d_->spectral; }

void SceneDescription::make_translucent_diffuse() {
  for (auto& m : d_->materials)
    if (m.translucent()) m.as_diffuse = true;
}

Scene SceneDescription::build(const util::ProgressCallback& progress) const {
  return std::move(render::build({this}, progress).front());
}

BuildWork SceneDescription::build_work() const { return render::build_work({this}); }

namespace {
std::vector<const SceneDescription::Data*> data_of(const std::vector<const SceneDescription*>& descriptions) {
  std::vector<const SceneDescription::Data*> data;
  for (const SceneDescription* d : descriptions) data.push_back(&d->data());
  return data;
}
}  // namespace

std::vector<Scene> build(const std::vector<const SceneDescription*>& descriptions,
                         const util::ProgressCallback& progress) {
  std::vector<Scene> out;
  for (SceneData& s : build_scenes(data_of(descriptions), progress)) out.push_back(make_scene(std::move(s)));
  return out;
}

BuildWork build_work(const std::vector<const SceneDescription*>& descriptions) {
  return build_work(data_of(descriptions));
}

bool Scene::spectral() const { return impl_->data.spectral; }

std::vector<Scene::MaterialValidity> Scene::validity() const {
  std::vector<MaterialValidity> out;
  for (const auto& m : impl_->data.materials)
    if (const TranslucentMaterial* t = m.translucent(); t != nullptr && !t->validity.ok())
      out.push_back({m.name, std::string(t->solver->name()), t->validity});
  return out;
}

int Scene::width() const { return impl_->data.camera.width; }
int Scene::height() const { return impl_->data.camera.height; }
double Scene::exposure() const { return impl_->data.exposure; }
ToneMap Scene::tone_map() const { return impl_->data.tone_map; }

std::string Scene::summary() const {
  std::size_t tris = 0;
  for (const auto& m : impl_->data.meshes) tris += m.triangles.size();
  std::ostringstream os;
  os << impl_->data.source << ": " << tris << " triangles, " << impl_->data.materials.size() << " materials, "
     << impl_->data.lights.size() << " lights";
  return os.str();
}

}  // namespace skin::render
