// The build of a scene's materials: from their descriptions (skin parameters, layer stacks) to
// the tabulated diffusion profiles the integrator samples (DJ06 section 4: the spectral profiles
// are converted to colour radius by radius; ProfileSolver::rgb applies the colour weights in the
// frequency domain), each distinct skin once (docs/renderer.md, "Describe, then build").
#include <tbb/parallel_for.h>

#include <algorithm>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

#include "scene_data.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

using skin::util::InputError;

using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::transport::SpectralProfile;

using skin::model::SkinProfiles;
using skin::model::skin_profiles;
using skin::model::skin_spectrum;

using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

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

// Albedo texture normalisation (DJ06 section 3.6): the texture is divided by the R_d colour of
// the chromophores assumed for it, so that subsurface light times the normalised texture
// reproduces the texture's own colour.
Rgb3 normalisation(const Rgb3& R_d) {
  Rgb3 n;
  for (int c = 0; c < 3; ++c) n[c] = R_d[c] > 1e-6 ? 1.0 / R_d[c] : 0.0;
  return n;
}

// The grid of the profiles' shapes and of the spectral profiles: 10 nm (the spectra are smooth
// at that scale and the transform costs in proportion to the number of wavelengths); the totals
// come from the paper's 2 nm grid (exact at k = 0 and cheap), so that R_d matches `skin color`.
WavelengthGrid shape_grid() { return WavelengthGrid(400.0, 700.0, 10.0); }

// One job of the build: a skin's profiles for a (parameters, solver, spectral).
struct SkinKey {
  SkinParameters p;
  const transport::Model* solver = nullptr;
  bool spectral = false;
  bool operator==(const SkinKey& o) const { return p == o.p && solver == o.solver && spectral == o.spectral; }
};
struct SkinResult {
  std::array<TabulatedProfile, 3> profile;
  Rgb3 R_d;
  transport::Validity validity;
  std::shared_ptr<const SpectralSkin> spectral;
  std::shared_ptr<const SpectralCurve> spectral_R_d;  // the skin's own R_d spectrum
};

SkinResult compute_skin(const SkinKey& k, const util::ProgressCallback& progress = {}) {
  ProfileSolver solver(skin_profile_radii());
  const SkinProfiles prof = skin_profiles(k.p, shape_grid(), solver, *k.solver,
                                            k.spectral ? std::optional(shape_grid()) : std::nullopt, progress);
  SkinResult r;
  r.validity = prof.validity;
  const auto total = prof.total.color.srgb_linear;
  for (int c = 0; c < 3; ++c) {
    const auto ci = static_cast<std::size_t>(c);
    r.R_d[c] = total[c];
    r.profile[ci] = TabulatedProfile(prof.rgb.radii.r, prof.rgb.R[ci], total[c]);
  }
  if (prof.spectral) {
    const SpectralProfile& sp = *prof.spectral;
    auto s = std::make_shared<SpectralSkin>();
    const std::size_t nr = sp.radii.size();
    s->profile.reserve(s->grid.size());
    for (std::size_t i = 0; i < s->grid.size(); ++i) {
      const std::vector<double> R(sp.R.begin() + static_cast<std::ptrdiff_t>(i * nr),
                                  sp.R.begin() + static_cast<std::ptrdiff_t>((i + 1) * nr));
      s->profile.emplace_back(sp.radii.r, R, sp.R_d[i]);
    }
    r.spectral = std::move(s);
    auto curve = std::make_shared<SpectralCurve>();
    curve->values = sp.R_d.values;
    r.spectral_R_d = std::move(curve);
  }
  return r;
}

struct LayeredResult {
  std::array<TabulatedProfile, 3> profile;
  Rgb3 R_d;
  transport::Validity validity;
};

LayeredResult compute_layered(const MaterialDescription& d) {
  LayeredResult r;
  const RadialGrid radii = skin_profile_radii();
  ProfileSolver solver(radii);
  for (int c = 0; c < 3; ++c) {
    const auto ci = static_cast<std::size_t>(c);
    const auto response = d.solver->response(d.stacks[ci]);  // validates (InputError names the layer)
    const std::vector<double> R = solver.profile(*response);
    r.R_d[c] = response->total();
    r.profile[ci] = TabulatedProfile(radii.r, R, r.R_d[c]);
  }
  r.validity = transport::combined_validity(*d.solver, {d.stacks.begin(), d.stacks.end()}, {"red", "green", "blue"});
  return r;
}

// The parameters at the nodes of a skin material's parameter maps (first map fastest).
std::vector<SkinParameters> node_parameters(const MaterialDescription& d) {
  std::size_t count = 1;
  for (const auto& mp : d.maps) count *= static_cast<std::size_t>(mp.levels);
  std::vector<SkinParameters> params(count, d.parameters);
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t rest = i;
    for (const auto& mp : d.maps) {
      const auto level = rest % static_cast<std::size_t>(mp.levels);
      rest /= static_cast<std::size_t>(mp.levels);
      params[i].*(mp.member) = mp.min + (mp.max - mp.min) * static_cast<double>(level) / (mp.levels - 1);
    }
    params[i].validate();  // InputError names the parameter and value
  }
  return params;
}

// The texture reference of a skin (DJ06 section 3.6), with the default model: its R_d colour,
// and its R_d spectrum for spectral rendering.
struct TextureReference {
  Rgb3 normalisation;
  std::shared_ptr<const SpectralCurve> spectral;
};

[[noreturn]] void rethrow_in(const std::string& source, const std::string& where, std::exception_ptr e) {
  try {
    std::rethrow_exception(e);
  } catch (const InputError& x) {
    throw InputError("scene = '" + source + "': " + where + ": " + x.what());
  }
}

}  // namespace

void check_spectral(const SceneDescription::Data& s) {
  for (const auto& m : s.materials)
    if (m.kind == MaterialKind::layered && !m.as_diffuse)
      throw InputError("spectral: material '" + m.name +
                       "' is layered (its stacks are given per RGB channel); spectral rendering needs skin or "
                       "diffuse materials");
}

namespace {

// The plan of a build: the distinct skins (materials and parameter-map nodes) and the layered
// materials, and what each material takes from them.
struct Plan {
  std::size_t key = 0;                  // skin
  std::vector<std::size_t> node_keys;   // skin with maps
  std::size_t layered = 0;              // layered
};
struct BuildPlan {
  std::vector<SkinKey> keys;
  std::vector<std::pair<const SceneDescription::Data*, const MaterialDescription*>> key_owner;  // for messages
  std::vector<std::vector<Plan>> plans;
  std::vector<std::pair<const SceneDescription::Data*, const MaterialDescription*>> layered;
};

BuildPlan plan_build(const std::vector<const SceneDescription::Data*>& descriptions) {
  BuildPlan b;
  auto& keys = b.keys;
  auto& key_owner = b.key_owner;
  const auto key_of = [&](const SceneDescription::Data* s, const MaterialDescription& d, const SkinParameters& p) {
    const SkinKey k{p, d.solver, s->spectral && !d.as_diffuse};
    const auto it = std::find(keys.begin(), keys.end(), k);
    if (it != keys.end()) return static_cast<std::size_t>(it - keys.begin());
    keys.push_back(k);
    key_owner.emplace_back(s, &d);
    return keys.size() - 1;
  };
  auto& plans = b.plans;
  plans.resize(descriptions.size());
  auto& layered = b.layered;
  for (std::size_t si = 0; si < descriptions.size(); ++si) {
    const SceneDescription::Data* s = descriptions[si];
    if (s->spectral) check_spectral(*s);
    for (const MaterialDescription& d : s->materials) {
      Plan plan;
      if (d.kind == MaterialKind::skin) {
        try {
          d.parameters.validate();
        } catch (const InputError&) {
          rethrow_in(s->source, "materials." + d.name, std::current_exception());
        }
        plan.key = key_of(s, d, d.parameters);
        if (!d.maps.empty() && !d.as_diffuse) {
          std::vector<SkinParameters> params;
          try {
            params = node_parameters(d);
          } catch (const InputError&) {
            rethrow_in(s->source, "materials." + d.name + ".parameter_maps", std::current_exception());
          }
          for (const SkinParameters& p : params) plan.node_keys.push_back(key_of(s, d, p));
        }
      } else if (d.kind == MaterialKind::layered) {
        plan.layered = layered.size();
        layered.emplace_back(s, &d);
      }
      plans[si].push_back(std::move(plan));
    }
  }
  return b;
}

// The wavelengths (skin) or channels (layered) of each job whose profile its solver computes
// numerically, in job order (the skins, then the layered materials); stacks that fail to build
// count as none (the build reports them).
std::vector<std::size_t> solved_per_job(const BuildPlan& b) {
  std::vector<std::size_t> out;
  for (const SkinKey& k : b.keys) {
    try {
      out.push_back(skin::model::skin_profile_solves(k.p, shape_grid(), *k.solver));
    } catch (const InputError&) {
      out.push_back(0);
    }
  }
  for (const auto& [s, d] : b.layered) {
    std::size_t n = 0;
    for (const LayerStack& stack : d->stacks) {
      try {
        n += d->solver->response_is_solved(stack) ? 1 : 0;
      } catch (const InputError&) {
      }
    }
    out.push_back(n);
  }
  return out;
}

}  // namespace

BuildWork build_work(const std::vector<const SceneDescription::Data*>& descriptions) {
  const BuildPlan b = plan_build(descriptions);
  BuildWork w;
  for (std::size_t n : solved_per_job(b)) w.solved += n;
  w.profiles = b.keys.size() * shape_grid().size() + 3 * b.layered.size();
  return w;
}

std::vector<SceneData> build_scenes(const std::vector<const SceneDescription::Data*>& descriptions,
                                    const util::ProgressCallback& progress) {
  const BuildPlan b = plan_build(descriptions);
  const auto& keys = b.keys;
  const auto& key_owner = b.key_owner;
  const auto& plans = b.plans;
  const auto& layered = b.layered;
  // The physics: every job once, in parallel; the first failure in plan order is reported.
  std::vector<SkinResult> skins(keys.size());
  std::vector<LayeredResult> layers(layered.size());
  std::vector<std::exception_ptr> failed(keys.size() + layered.size());
  const auto job = [&](std::size_t i, const util::ProgressCallback& p) {
    try {
      if (i < keys.size()) skins[i] = compute_skin(keys[i], p);
      else layers[i - keys.size()] = compute_layered(*layered[i - keys.size()].second);
    } catch (...) {
      failed[i] = std::current_exception();
    }
  };
  // The jobs that only read tables (milliseconds each) all at once; with a progress callback, the
  // jobs that solve profiles (each solve parallel inside) one after the other, so that progress
  // is reported per wavelength from this thread.
  std::vector<std::size_t> quick, solving;
  const std::vector<std::size_t> solved = progress ? solved_per_job(b) : std::vector<std::size_t>(failed.size(), 0);
  for (std::size_t i = 0; i < failed.size(); ++i) (solved[i] > 0 ? solving : quick).push_back(i);
  tbb::parallel_for(std::size_t{0}, quick.size(), [&](std::size_t q) { job(quick[q], {}); });
  std::size_t total = 0, done = 0;
  for (std::size_t i : solving) total += i < keys.size() ? shape_grid().size() : 3;
  for (std::size_t i : solving) {
    util::cancel::check();
    job(i, [&](std::size_t d, std::size_t) { progress(done + d, total); });
    done += i < keys.size() ? shape_grid().size() : 3;
    progress(done, total);
  }
  for (std::size_t i = 0; i < failed.size(); ++i)
    if (failed[i]) {
      const auto& [s, d] = i < keys.size() ? key_owner[i] : layered[i - keys.size()];
      rethrow_in(s->source, "materials." + d->name, failed[i]);
    }
  // The materials.
  std::vector<SceneData> out(descriptions.size());
  for (std::size_t si = 0; si < descriptions.size(); ++si) {
    const SceneDescription::Data& s = *descriptions[si];
    SceneData& data = out[si];
    static_cast<SceneSetup&>(data) = static_cast<const SceneSetup&>(s);
    for (std::size_t mi = 0; mi < s.materials.size(); ++mi) {
      const MaterialDescription& d = s.materials[mi];
      const Plan& plan = plans[si][mi];
      Material m;
      m.name = d.name;
      if (d.kind == MaterialKind::diffuse) {
        m.type = DiffuseMaterial{d.albedo, d.albedo_map};
      } else if (d.as_diffuse) {  // albedo its R_d
        m.type = DiffuseMaterial{d.kind == MaterialKind::skin ? skins[plan.key].R_d : layers[plan.layered].R_d, nullptr};
      } else if (d.kind == MaterialKind::layered) {
        const LayeredResult& r = layers[plan.layered];
        TranslucentMaterial t;
        t.solver = d.solver;
        t.albedo_map = d.albedo_map;
        t.rho_s = d.rho_s;
        t.roughness = d.roughness;
        t.eta = d.eta;
        t.profile = r.profile;
        t.R_d = r.R_d;
        t.validity = r.validity;
        t.texture_normalisation = normalisation(t.R_d);
        t.specular_albedo = specular_albedo(t.roughness, t.eta);
        m.type = std::move(t);
      } else {
        std::optional<TextureReference> ref;
        if (d.texture_reference) {
          ref.emplace();
          ref->normalisation = normalisation(skin_spectrum(*d.texture_reference).color.srgb_linear);
          if (s.spectral) {
            auto curve = std::make_shared<SpectralCurve>();
            curve->values = skin_spectrum(*d.texture_reference, curve->grid).R_d.values;
            ref->spectral = std::move(curve);
          }
        }
        const auto skin = [&](const SkinParameters& p, std::size_t key) {
          const SkinResult& r = skins[key];
          TranslucentMaterial n;
          n.solver = d.solver;
          n.albedo_map = d.albedo_map;
          n.rho_s = p.oiliness;
          n.roughness = p.roughness;
          n.eta = p.eta;
          n.profile = r.profile;
          n.R_d = r.R_d;
          n.validity = r.validity;
          n.texture_normalisation = ref ? ref->normalisation : normalisation(n.R_d);
          n.spectral = r.spectral;
          n.spectral_texture_reference = ref ? ref->spectral : r.spectral_R_d;
          n.specular_albedo = specular_albedo(n.roughness, n.eta);
          return n;
        };
        TranslucentMaterial t = skin(d.parameters, plan.key);
        if (!plan.node_keys.empty()) {
          t.maps = d.maps;
          const std::vector<SkinParameters> params = node_parameters(d);
          for (std::size_t i = 0; i < params.size(); ++i) t.nodes.push_back(skin(params[i], plan.node_keys[i]));
        }
        m.type = std::move(t);
      }
      data.materials.push_back(std::move(m));
    }
  }
  return out;
}

TranslucentMaterial build_translucent(const MaterialDescription& d, bool spectral) {
  SKIN_ASSERT(d.translucent(), "build_translucent of a diffuse material");
  SceneDescription::Data data;
  data.source = "material '" + d.name + "'";
  data.spectral = spectral;
  data.materials = {d};
  return std::get<TranslucentMaterial>(std::move(build_scenes({&data}).front().materials.front().type));
}

MaterialDescription skin_description(const SkinParameters& p, const transport::Model& solver) {
  MaterialDescription d;
  d.kind = MaterialKind::skin;
  d.parameters = p;
  d.solver = &solver;
  return d;
}

MaterialDescription layered_description(const std::array<LayerStack, 3>& stacks, const transport::Model& solver) {
  MaterialDescription d;
  d.kind = MaterialKind::layered;
  d.stacks = stacks;
  d.solver = &solver;
  return d;
}

const TranslucentMaterial& TranslucentMaterial::node_at(double u, double v, double xi) const {
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

}  // namespace skin::render
