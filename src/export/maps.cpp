// Parameter maps (target.hpp): every distinct texel fitted through a target that takes
// textures, and the two textures of the result.
#include <algorithm>
#include <map>
#include <mutex>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "target.hpp"
#include "skin/util/error.hpp"

namespace skin::exporting::detail {

using skin::util::InputError;
using skin::util::ProgressCallback;

using skin::transport::ProfileSolver;

using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::parameter_info;

MapsFit fit_maps(TexelFit (*texel)(const Reference&), const SkinParameters& base,
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
      [] { return ProfileSolver(reference_radii()); });
  std::mutex m;
  std::size_t done = 0;
  tbb::parallel_for(std::size_t{0}, distinct.size(), [&](std::size_t d) {
    const Reference ref = make_reference(sets[d], model, solvers.local());
    fits[d] = texel(ref);
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

}  // namespace skin::exporting::detail
