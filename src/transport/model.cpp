// The registry of transport models (include/skin/transport/model.hpp): the multipole (DJ05
// diffusion, skin::transport::DiffusionStack) and the accurate model (adding-doubling totals, transport-table
// profiles, skin::transport::accurate::AccurateStack).
#include "skin/transport/model.hpp"

#include <array>
#include <mutex>
#include <ostream>
#include <sstream>

#include "skin/physics/fresnel.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/diffusion.hpp"
#include "skin/transport/stack.hpp"
#include "skin/util/error.hpp"

namespace skin::transport {

using skin::util::InputError;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::fresnel_dielectric;

std::ostream& operator<<(std::ostream& os, const Totals& t) {
  return os << "Totals{R_specular=" << t.R_specular << ", R_d=" << t.R_d << ", T_d=" << t.T_d
            << '}';
}

std::ostream& operator<<(std::ostream& os, const Validity& v) {
  os << "Validity{totals=" << v.totals << ", profile=" << v.profile;
  if (!v.reason.empty()) os << ", reason=\"" << v.reason << '"';
  if (!v.exact.empty()) os << ", exact=\"" << v.exact << '"';
  return os << '}';
}

std::string warning_text(std::string_view model, const Validity& v, const std::string& what) {
  if (v.ok()) return {};
  std::string text = "solver " + std::string(model) + (what.empty() ? "" : " for " + what) + ": " +
                     (v.totals ? "profile" : v.profile ? "totals" : "totals and profile") +
                     " outside its validated range: " + v.reason;
  if (!v.exact.empty()) text += "; still exact: " + v.exact;
  return text;
}

namespace {

// DJ05 diffusion (include/skin/transport/diffusion.hpp, stack.hpp).
class Multipole final : public Model {
 public:
  std::string_view name() const override { return "multipole"; }
  std::string_view description() const override {
    return "the paper's DJ05 diffusion model";
  }
  Totals totals(const LayerStack& stack) const override {
    const DiffusionStack ds(stack);
    const Transfer t = ds.at(0.0);
    return {fresnel_dielectric(1.0, stack.eta_above, stack.layers.front().eta), t.R_down,
            t.T_down};
  }
  double R_d(const LayerStack& stack) const override { return DiffusionStack(stack).R_d(); }
  std::unique_ptr<RadialResponse> response(const LayerStack& stack) const override {
    return std::make_unique<DiffusionStack>(stack);
  }
  bool response_is_solved(const LayerStack&) const override { return false; }
  // The real source of each layer sits at z_r = 1 / sigma_t' (DJ05 eq 7): in a layer thinner
  // than that it lies below the layer, the layer's transmittance changes sign and R_d jumps
  // (docs/fit.md, "Validity"). Totals and profile are then both outside the model.
  Validity validity(const LayerStack& stack) const override {
    Validity v;
    for (std::size_t i = 0; i < stack.layers.size(); ++i) {
      const Layer& l = stack.layers[i];
      const double tau_prime = l.thickness * (l.sigma_a + l.sigma_s_prime);
      if (!l.semi_infinite() && tau_prime <= 1.0) {
        std::ostringstream os;
        os.precision(3);
        os << "layer " << i + 1 << " is thinner than z_r = 1/sigma_t' (d = " << l.thickness
           << " mm, z_r = " << 1.0 / (l.sigma_a + l.sigma_s_prime)
           << " mm): diffusion's source lies below it";
        v.totals = v.profile = false;
        v.reason = os.str();
        return v;
      }
    }
    return v;
  }
};

// Adding-doubling totals (include/skin/transport/accurate.hpp) with the cache (accurate::Cache)
// shared by every caller and thread; valid for every valid stack. The two models below differ
// only in their profiles.
class AddingDoublingModel : public Model {
 public:
  Totals totals(const LayerStack& stack) const override {
    return accurate::adding_doubling(stack, {}, cache_);
  }
  Validity validity(const LayerStack& stack) const override {
    stack.validate();
    return {};
  }

 protected:
  accurate::Cache cache_;
};

// Profiles of skin (and half-spaces of its medium) from the table of frequency-domain profiles
// (skin_stack_table.hpp), of every other stack from radiative transfer in the spatial-frequency
// domain (AccurateStack).
class Accurate final : public AddingDoublingModel {
 public:
  std::string_view name() const override { return "accurate"; }
  std::string_view description() const override {
    return "adding-doubling radiative transfer, within Monte Carlo noise";
  }
  std::unique_ptr<RadialResponse> response(const LayerStack& stack) const override {
    return std::make_unique<accurate::AccurateStack>(stack, accurate::Options{}, cache_);
  }
  bool response_is_solved(const LayerStack& stack) const override {
    return !accurate::AccurateStack::reads_table(stack);
  }
};

// Profiles by radiative transfer in the spatial-frequency domain for every stack
// (accurate::FrequencyStack), skin included: no tables, ~0.1-1 CPU-s per stack.
class Frequency final : public AddingDoublingModel {
 public:
  std::string_view name() const override { return "sfd"; }
  std::string_view description() const override {
    return "adding-doubling radiative transfer, profiles in the spatial-frequency domain";
  }
  std::unique_ptr<RadialResponse> response(const LayerStack& stack) const override {
    return std::make_unique<accurate::FrequencyStack>(stack, accurate::FrequencyProfileOptions{},
                                                      cache_);
  }
  bool response_is_solved(const LayerStack&) const override { return true; }
};

// The models, the default first.
const std::array<const Model*, 3>& registry() {
  static const Accurate accurate_model;
  static const Multipole multipole_model;
  static const Frequency frequency_model;
  static const std::array<const Model*, 3> models = {&accurate_model, &multipole_model,
                                                     &frequency_model};
  return models;
}

}  // namespace

const Model& find_model(std::string_view name) {
  for (const Model* m : registry())
    if (m->name() == name) return *m;
  throw InputError("solver = '" + std::string(name) + "' is unknown: allowed values are " +
                   model_names_text());
}

const Model& default_model() { return find_model(kDefaultModel); }

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const Model* m : registry()) names.emplace_back(m->name());
  return names;
}

std::string model_names_text() {
  std::string text;
  for (const auto& n : model_names()) text += (text.empty() ? "" : ", ") + n;
  return text;
}

Validity combined_validity(const Model& model, const std::vector<LayerStack>& stacks,
                           const std::vector<std::string>& labels) {
  const auto label = [&](std::size_t i) { return i < labels.size() ? labels[i] : std::to_string(i); };
  Validity out;
  std::size_t count = 0, first = 0, last = 0;
  for (std::size_t i = 0; i < stacks.size(); ++i) {
    Validity v = model.validity(stacks[i]);
    if (v.ok()) continue;
    if (count++ == 0) {
      first = i;
      out.reason = std::move(v.reason);
      out.exact = std::move(v.exact);
    }
    out.totals = out.totals && v.totals;
    out.profile = out.profile && v.profile;
    last = i;
  }
  if (count > 0)
    out.reason = "at " + label(first) + (count > 1 ? " .. " + label(last) : "") + " (" +
                 std::to_string(count) + " of " + std::to_string(stacks.size()) + "): " + out.reason;
  return out;
}

}  // namespace skin::transport
