#pragma once
// Transport models of a layer stack, one interface, chosen by name. A model gives, for a
// LayerStack, its totals (R_specular, R_d, T_d), the radial response that skin::transport::ProfileSolver
// inverts into R(r), and whether the stack lies inside the range where the model has been
// validated (and why not). The registry holds every model by name and the one default; callers
// (the skin model, the fit, the renderer, the CLI's --solver, Python's solver=) never branch on
// the kind of model.
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "skin/physics/layer.hpp"
#include "skin/transport/profile_fwd.hpp"

namespace skin::transport {

struct Totals {
  double R_specular = 0;  // Fresnel reflectance of the top surface at normal incidence
  double R_d = 0;         // diffuse reflectance per power that entered
  double T_d = 0;         // total transmittance per power that entered (0 if semi-infinite)
};
std::ostream& operator<<(std::ostream& os, const Totals& t);

// Whether a stack lies inside a model's validated range. Outside it the model still returns
// numbers (they are never clamped); the caller reports the reason.
struct Validity {
  bool totals = true;   // R_d and T_d within the model's stated accuracy
  bool profile = true;  // the shape of R(r) within it
  std::string reason;   // why not (empty when both hold)
  std::string exact;    // what stays exact when only the profile is out (e.g. "R_d and T_d")
  bool ok() const { return totals && profile; }
};
std::ostream& operator<<(std::ostream& os, const Validity& v);
// The one-line warning every surface shows for a stack outside `model`'s range ("" when ok):
// "solver accurate[ for WHAT]: profile outside its validated range: REASON; still exact: ...".
std::string warning_text(std::string_view model, const Validity& v, const std::string& what = "");

class Model {
 public:
  virtual ~Model() = default;
  // The name the registry, --solver, the JSON key `solver` and Python's solver= use.
  virtual std::string_view name() const = 0;
  // One line for help texts.
  virtual std::string_view description() const = 0;
  // Validates the stack (InputError naming the layer and parameter).
  virtual Totals totals(const physics::LayerStack& stack) const = 0;
  // R_d alone (models may compute it more cheaply than all the totals).
  virtual double R_d(const physics::LayerStack& stack) const { return totals(stack).R_d; }
  // The radial response (total == R_d); validates the stack.
  virtual std::unique_ptr<RadialResponse> response(const physics::LayerStack& stack) const = 0;
  virtual Validity validity(const physics::LayerStack& stack) const = 0;
  // Whether response() solves the stack numerically (the frequency-domain solver) rather than
  // evaluating a closed form or reading a table, which is orders of magnitude cheaper
  // (docs/benchmarks.md). Interactive callers (the web page) ask before they build many
  // responses.
  virtual bool response_is_solved(const physics::LayerStack& stack) const = 0;
};

// The models (model_names()):
// - accurate, the default: totals by the adding-doubling method (radiative transfer with a
//   Henyey-Greenstein phase function, exact Fresnel boundaries), within Monte Carlo noise for
//   every skin type; profiles by radiative transfer in the spatial-frequency domain (as `sfd`),
//   read from the built-in table of skin profiles for the two-layer skin geometry and the
//   half-space of skin's medium (every preset), solved for every other stack; integrating
//   exactly to those totals (docs/accurate-solver.md, sec. 3-5).
// - sfd: the same totals, every profile from the spatial-frequency domain (accurate::
//   FrequencyStack): within 5 % + 3 SE of Monte Carlo over 0.02-10 mm in every case measured
//   (against `skin mc` and MCML; a slab thinner than ~0.023 scaled mean free paths reaches the
//   cap of 64 azimuthal orders and may miss near the beam). Its cost per stack grows with the
//   layers, the index steps and the azimuthal orders a thin slab needs (docs/benchmarks.md).
// - multipole: the paper's method (DJ05 multipole, convolved in the frequency domain), kept
//   unchanged to reproduce the paper; outside it where a layer is thinner than z_r.
// The default is accurate because the multipole overstates dark skin's reflectance 2-3x in the
// blue, and the colour follows the totals and the BSSRDF the profiles. This is the one place the
// default is decided (the CLI's --solver, the JSON key `solver`, Python's solver=, the scene
// key `solver` and the fit all take it from here).
inline constexpr std::string_view kDefaultModel = "accurate";

// The registered models, by name; InputError listing the known names otherwise.
const Model& find_model(std::string_view name);
const Model& default_model();
// Registered names, the default first.
std::vector<std::string> model_names();
// "accurate, multipole": for messages and help texts.
std::string model_names_text();

// Several stacks of one material (per wavelength, per channel): the first stack outside the
// range gives the reason, preceded by the labels of the first and last stacks out and how many
// are ("at 400 nm .. 452 nm (27 of 151): ..."); `labels[i]` names stack i.
Validity combined_validity(const Model& model, const std::vector<physics::LayerStack>& stacks,
                           const std::vector<std::string>& labels);

}  // namespace skin::transport
