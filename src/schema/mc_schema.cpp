// The schema of skin mc (mc_schema.hpp).
#include "mc_schema.hpp"

#include <cstdio>

#include "skin/util/error.hpp"

namespace skin::schema {

using skin::util::format_number;

using skin::physics::Layer;
using skin::physics::LayerStack;

Result mc_result(const LayerStack& stack, const mc::Result& r, std::uint64_t seed,
                 const std::optional<McSkin>& skin) {
  Result result;
  json& j = result.document;
  j["solver"] = "monte-carlo";
  if (skin) {
    j["preset"] = skin->preset;
    j["parameters"] = to_json(skin->parameters);
    j["wavelength_nm"] = skin->wavelength_nm;
  }
  j["eta_above"] = stack.eta_above;
  j["eta_below"] = stack.eta_below;
  json layers = json::array();
  for (const Layer& l : stack.layers) {
    json jl = to_json(l);
    jl["sigma_s"] = l.sigma_s();
    layers.push_back(jl);
  }
  j["layers"] = layers;
  j["R_specular"] = r.R_specular;
  j["R_d"] = r.R_d;
  j["R_d_se"] = r.R_d_se;
  j["T_d"] = r.T_d;
  j["T_d_se"] = r.T_d_se;
  j["R_d_incident"] = r.R_d_incident;
  j["T_d_incident"] = r.T_d_incident;
  j["lost"] = r.lost;
  j["photons"] = r.photons;
  j["seed"] = seed;
  j["seconds"] = r.seconds;
  j["profile"] = {{"r_mm", r.r_mm}, {"R", r.R}, {"R_se", r.R_se}};
  // Totals per power that entered, as columns beside the profile.
  const std::size_t n = r.r_mm.size();
  result.columns = {{"r_mm", r.r_mm, {}},
                    {"R [1/mm^2]", r.R, {}},
                    {"R_se [1/mm^2]", r.R_se, {}},
                    constant_column("R_d", r.R_d, n),
                    constant_column("R_d_se", r.R_d_se, n),
                    constant_column("T_d", r.T_d, n),
                    constant_column("T_d_se", r.T_d_se, n),
                    constant_column("R_specular", r.R_specular, n),
                    constant_column("photons", static_cast<double>(r.photons), n)};
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "per power that entered:  R_d %.6f +- %.6f   T_d %.6f +- %.6f\n"
                "per incident power:      R_d %.6f   T_d %.6f   R_specular %.6f\n"
                "%llu photons in %.2f s\n",
                r.R_d, r.R_d_se, r.T_d, r.T_d_se, r.R_d_incident, r.T_d_incident, r.R_specular,
                static_cast<unsigned long long>(r.photons), r.seconds);
  result.table = buf;
  if (r.lost > 0)
    result.table += "lost " + format_number(r.lost) +
                    " of the weight: packets ended after the longest path allowed (a nearly "
                    "non-absorbing medium)\n";
  result.table += "\n" + format_table({"r_mm", "R [1/mm^2]", "R_se"}, {r.r_mm, r.R, r.R_se});
  return result;
}

}  // namespace skin::schema
