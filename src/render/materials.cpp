// Translucent materials: from skin parameters or layer stacks to the tabulated RGB diffusion
// profiles the integrator samples (DJ06 section 4: the spectral profiles are converted to colour
// radius by radius; ProfileSolver::rgb applies the colour weights in the frequency domain).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <utility>

#include "scene_data.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/util/error.hpp"

namespace skin::render {
// r = 0, then logarithmic from 1 um to 20 mm: dense where the profile is peaked, reaching far
// enough for the red channel of pale skin (its 1/sigma_tr is a few mm; at 20 mm R(r) is below
// 1e-6 of R(0)). The transform's cost grows with the largest radius (panels no wider than a
// period of J0 there), so the grid stops where the tail no longer matters; the truncated tail's
// energy is restored by TabulatedProfile's rescaling to the exact R_d.
RadialGrid skin_profile_radii() {
  std::vector<double> r{0.0};
  const RadialGrid g = RadialGrid::logarithmic(1e-3, 20.0, 128);
  r.insert(r.end(), g.r.begin(), g.r.end());
  return RadialGrid::from(std::move(r));
}

namespace {

std::shared_ptr<const SpecularAlbedo> specular_albedo(double roughness, double eta) {
  static std::mutex mutex;
  static std::map<std::pair<double, double>, std::shared_ptr<const SpecularAlbedo>> cache;
  const std::lock_guard lock(mutex);
  auto& slot = cache[{roughness, eta}];
  if (!slot) slot = std::make_shared<SpecularAlbedo>(roughness, eta);
  return slot;
}

}  // namespace

void prepare_skin_material(Material& m, const SkinParameters& p) {
  p.validate();
  m.kind = MaterialKind::skin;
  m.parameters = p;
  m.spectral = nullptr;  // stale: prepare_spectral rebuilds it
  m.rho_s = p.oiliness;
  m.roughness = p.roughness;
  m.eta = p.eta;
  ProfileSolver solver(skin_profile_radii());
  // The shape of each channel's profile from a 10 nm grid (the spectra are smooth at that scale
  // and the transform costs in proportion to the number of wavelengths), its total from the
  // paper's 2 nm grid (exact at k = 0 and cheap), so that R_d matches `skin color` exactly.
  const WavelengthGrid shape_grid(400.0, 700.0, 10.0);
  const RgbProfile prof = skin_rgb_profile(p, shape_grid, solver, *m.solver);
  const auto total = skin_spectrum(p, WavelengthGrid(), *m.solver).color.srgb_linear;
  m.validity = skin_validity(p, shape_grid, *m.solver);
  for (int c = 0; c < 3; ++c) {
    const auto ci = static_cast<std::size_t>(c);
    m.R_d[c] = total[c];
    m.profile[ci] = TabulatedProfile(prof.radii.r, prof.R[ci], total[c]);
  }
  // Albedo texture normalisation (DJ06 section 3.6): the texture is divided by the R_d colour
  // of the chromophore values assumed for it (these parameters), so that subsurface light times
  // the normalised texture reproduces the texture's own colour.
  if (!m.texture_reference_fixed)
    for (int c = 0; c < 3; ++c) m.texture_normalisation[c] = m.R_d[c] > 1e-6 ? 1.0 / m.R_d[c] : 0.0;
  m.specular_albedo = specular_albedo(m.roughness, m.eta);
}

void set_texture_reference(Material& m, const SkinParameters& reference) {
  const auto rgb = skin_spectrum(reference).color.srgb_linear;
  for (int c = 0; c < 3; ++c) m.texture_normalisation[c] = rgb[c] > 1e-6 ? 1.0 / rgb[c] : 0.0;
  m.texture_reference_fixed = true;
  m.texture_reference = reference;
}

void prepare_parameter_maps(Material& m, const SkinParameters& p) {
  if (m.maps.empty()) return;
  std::size_t count = 1;
  for (const auto& mp : m.maps) count *= static_cast<std::size_t>(mp.levels);
  m.nodes.assign(count, Material{});
  std::vector<SkinParameters> params(count, p);
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t rest = i;
    for (const auto& mp : m.maps) {
      const auto level = rest % static_cast<std::size_t>(mp.levels);
      rest /= static_cast<std::size_t>(mp.levels);
      params[i].*(mp.member) = mp.min + (mp.max - mp.min) * static_cast<double>(level) / (mp.levels - 1);
    }
    params[i].validate();  // InputError names the parameter and value
  }
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    m.nodes[i].solver = m.solver;
    prepare_skin_material(m.nodes[i], params[i]);
  });
  for (auto& n : m.nodes) {
    n.albedo_map = m.albedo_map;
    if (m.texture_reference_fixed) {
      n.texture_normalisation = m.texture_normalisation;
      n.texture_reference_fixed = true;
      n.texture_reference = m.texture_reference;
    }
  }
}

const Material& Material::node_at(double u, double v, double xi) const {
  // Pick one corner of the grid cell per map dimension, each with its linear weight, using
  // successive bits of xi (stretched to stay uniform).
  std::size_t index = 0, stride = 1;
  for (const auto& mp : maps) {
    const double texel = mp.texture->lookup(u, v).r;  // data, not colour
    const double t = mp.values ? (texel - mp.min) / (mp.max - mp.min) : texel;
    const double x = std::clamp(t, 0.0, 1.0) * (mp.levels - 1);
    const auto lo = std::min(static_cast<std::size_t>(x), static_cast<std::size_t>(mp.levels - 2));
    const double w_hi = x - static_cast<double>(lo);
    std::size_t level = lo;
    if (xi < w_hi) {
      level = lo + 1;
      xi = xi / w_hi;
    } else {
      xi = w_hi < 1 ? (xi - w_hi) / (1 - w_hi) : 0.0;
    }
    index += level * stride;
    stride *= static_cast<std::size_t>(mp.levels);
  }
  return nodes[index];
}

void prepare_spectral(SceneData& s) {
  std::vector<Material*> todo;
  for (auto& m : s.materials) {
    if (m.kind == MaterialKind::layered)
      throw InputError("spectral: material '" + m.name +
                       "' is layered (its stacks are given per RGB channel); spectral rendering needs skin or "
                       "diffuse materials");
    if (m.kind != MaterialKind::skin) continue;
    if (!m.spectral) todo.push_back(&m);
    for (auto& n : m.nodes)
      if (!n.spectral) todo.push_back(&n);
  }
  tbb::parallel_for(std::size_t{0}, todo.size(), [&](std::size_t i) { todo[i]->spectral = make_spectral_skin(*todo[i]); });
}

void prepare_layered_material(Material& m, const std::array<LayerStack, 3>& stacks) {
  m.kind = MaterialKind::layered;
  m.stacks = stacks;
  const RadialGrid radii = skin_profile_radii();
  ProfileSolver solver(radii);
  for (int c = 0; c < 3; ++c) {
    const auto ci = static_cast<std::size_t>(c);
    const auto response = m.solver->response(stacks[ci]);  // validates (InputError names the layer)
    const std::vector<double> R = solver.profile(*response);
    m.R_d[c] = response->total();
    m.profile[ci] = TabulatedProfile(radii.r, R, m.R_d[c]);
  }
  m.validity = transport::combined_validity(*m.solver, {stacks.begin(), stacks.end()},
                                            {"red", "green", "blue"});
  for (int c = 0; c < 3; ++c) m.texture_normalisation[c] = m.R_d[c] > 1e-6 ? 1.0 / m.R_d[c] : 0.0;
  m.specular_albedo = specular_albedo(m.roughness, m.eta);
}

}  // namespace skin::render
