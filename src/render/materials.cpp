// Translucent materials: from skin parameters or layer stacks to the tabulated RGB diffusion
// profiles the integrator samples (DJ06 section 4: the spectral profiles are converted to colour
// radius by radius; ProfileSolver::rgb applies the colour weights in the frequency domain).
#include <map>
#include <mutex>
#include <utility>

#include "scene_data.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/physics/error.hpp"

namespace skin::render {
namespace {

// r = 0, then logarithmic from 1 um to 20 mm: dense where the profile is peaked, reaching far
// enough for the red channel of pale skin (its 1/sigma_tr is a few mm; at 20 mm R(r) is below
// 1e-6 of R(0)). The transform's cost grows with the largest radius (panels no wider than a
// period of J0 there), so the grid stops where the tail no longer matters; the truncated tail's
// energy is restored by TabulatedProfile's rescaling to the exact R_d.
RadialGrid profile_radii() {
  std::vector<double> r{0.0};
  const RadialGrid g = RadialGrid::logarithmic(1e-3, 20.0, 128);
  r.insert(r.end(), g.r.begin(), g.r.end());
  return RadialGrid::from(std::move(r));
}

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
  m.rho_s = p.oiliness;
  m.roughness = p.roughness;
  m.eta = p.eta;
  ProfileSolver solver(profile_radii());
  // The shape of each channel's profile from a 10 nm grid (the spectra are smooth at that scale
  // and the transform costs in proportion to the number of wavelengths), its total from the
  // paper's 2 nm grid (exact at k = 0 and cheap), so that R_d matches `skin color` exactly.
  const RgbProfile prof = skin_rgb_profile(p, WavelengthGrid(400.0, 700.0, 10.0), solver);
  const auto total = skin_spectrum(p).color.srgb_linear;
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
}

void prepare_layered_material(Material& m, const std::array<LayerStack, 3>& stacks) {
  m.kind = MaterialKind::layered;
  const RadialGrid radii = profile_radii();
  ProfileSolver solver(radii);
  for (int c = 0; c < 3; ++c) {
    const auto ci = static_cast<std::size_t>(c);
    const DiffusionStack ds(stacks[ci]);  // validates (InputError names the layer)
    const std::vector<double> R = solver.profile(ds);
    m.R_d[c] = ds.R_d();
    m.profile[ci] = TabulatedProfile(radii.r, R, ds.R_d());
  }
  for (int c = 0; c < 3; ++c) m.texture_normalisation[c] = m.R_d[c] > 1e-6 ? 1.0 / m.R_d[c] : 0.0;
  m.specular_albedo = specular_albedo(m.roughness, m.eta);
}

}  // namespace skin::render
