// skin layers: a transport model (--solver) of any layer stack given by its coefficients.
#include <algorithm>

#include "common.hpp"
#include "skin/util/error.hpp"
#include "skin/transport/profile.hpp"
#include "skin/transport/stack.hpp"
#include "skin/physics/fresnel.hpp"
#include "skin/transport/model.hpp"

namespace skin::cli {

using skin::util::require_non_negative;

using skin::transport::DiffusionStack;
using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;

using skin::physics::LayerStack;

void register_layers(CLI::App& app) {
  struct Opts {
    StackOptions stack;
    std::vector<double> radii;
    SolverOption solver;
    OutputOptions out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "layers",
      "Diffuse reflectance and transmittance of a stack of layers (per power that entered the "
      "top surface; accurate = adding-doubling, multipole = DJ05 diffusion), lengths in mm, "
      "coefficients in 1/mm");
  o->stack.add_to(*sub)->required();
  sub->add_option("--radius", o->radii, "Radius [mm] at which to print the profile R(r) (repeatable)")
      ->allow_extra_args(false);
  o->solver.add_to(*sub);
  o->out.add_to(*sub);
  sub->callback([o] {
    const LayerStack stack = o->stack.resolve();
    const DiffusionStack ds(stack);  // validates; its slabs describe the layers in the JSON
    const transport::Model& model = o->solver.model();
    const transport::Totals totals = model.totals(stack);
    // The profile is computed on the sorted distinct radii and reported in the order asked.
    const std::vector<double> r = o->radii;
    for (double x : r) require_non_negative("radius", x, "mm");
    std::vector<double> sorted = r;
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    std::vector<double> R;
    if (!r.empty()) {
      ProfileSolver solver(RadialGrid::from(sorted));
      const std::vector<double> on_sorted = solver.profile(*model.response(stack));
      for (double x : r)
        R.push_back(on_sorted[static_cast<std::size_t>(
            std::lower_bound(sorted.begin(), sorted.end(), x) - sorted.begin())]);
    }
    const transport::Validity validity = model.validity(stack);
    // The profile's validity matters only where one is computed; the totals' always.
    if (!validity.totals || (!r.empty() && !validity.profile)) warn_validity(model, validity);
    warn_if_negative("R_d", {totals.R_d}, {0.0}, "(total)");
    warn_if_negative("T_d", {totals.T_d}, {0.0}, "(total)");
    if (!R.empty()) warn_if_negative("R(r)", R, r, "mm");
    o->out.write(schema::layers_result(stack, ds, o->solver.name, totals, r, R, validity));
  });
}

SKIN_REGISTER_COMMAND(30, register_layers);

}  // namespace skin::cli
