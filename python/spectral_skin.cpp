// Python bindings: a thin layer over the C++ API. The parameter keywords are the parameter table's
// keys (the CLI flags with underscores, the JSON keys) or the paper's symbols. No logic here
// beyond converting types.
#include <cmath>
#include <map>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "skin/model/skin_model.hpp"
#include "skin/transport/model.hpp"
#include "skin/util/error.hpp"

namespace py = pybind11;
using namespace skin;

namespace {

// The preset's parameters, overridden by the keywords: each a key of the parameter table, its
// CLI spelling or the paper's symbol; None leaves the preset's value. Ranges: validate().
SkinParameters parameters(const std::string& preset, const py::kwargs& kw) {
  SkinParameters p = find_preset(preset).parameters;
  std::map<const ParameterInfo*, std::string> given;  // the keyword each parameter came as
  for (auto item : kw) {
    const auto name = py::cast<std::string>(item.first);
    const ParameterInfo& info = parameter_info(name);
    if (const auto [it, fresh] = given.emplace(&info, name); !fresh)
      throw InputError(std::string(info.key) + " is given twice: " + it->second + " and " + name +
                       " name the same parameter");
    if (item.second.is_none()) continue;
    try {
      if (py::isinstance<py::bool_>(item.second)) throw py::cast_error();
      p.*(info.member) = py::cast<double>(item.second);
    } catch (const py::cast_error&) {
      throw InputError(std::string(info.key) + " must be a number, not " +
                       py::cast<std::string>(py::repr(item.second)));
    }
  }
  p.validate();
  return p;
}

// The same object as the CLI's JSON "parameters": every key of the table with its value.
py::dict parameters_dict(const SkinParameters& p) {
  py::dict d;
  for (const ParameterInfo& info : parameter_table()) d[py::cast(info.key)] = p.*(info.member);
  return d;
}

py::object bound(double v) { return std::isinf(v) ? py::object(py::none()) : py::float_(v); }

py::dict color_dict(const color::ColorSummary& c) {
  py::dict d;
  d["XYZ"] = std::vector<double>{c.XYZ.X, c.XYZ.Y, c.XYZ.Z};
  d["srgb_linear"] = std::vector<double>{c.srgb_linear.r, c.srgb_linear.g, c.srgb_linear.b};
  d["srgb8"] = std::vector<int>{c.srgb8[0], c.srgb8[1], c.srgb8[2]};
  d["hex"] = c.hex;
  d["lab"] = std::vector<double>{c.lab.L, c.lab.a, c.lab.b};
  return d;
}

// {"totals": bool, "profile": bool, "reason": str}; a RuntimeWarning names the reason when the
// stack is outside the model's validated range (as the CLI's one warning line does).
py::dict validity_dict(const transport::Validity& v, const transport::Model& model,
                       bool warn = true) {
  if (warn && !v.ok()) {
    const std::string text = transport::warning_text(model.name(), v);
    if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) throw py::error_already_set();
  }
  return py::dict(py::arg("totals") = v.totals, py::arg("profile") = v.profile,
                  py::arg("reason") = v.reason);
}

}  // namespace

PYBIND11_MODULE(spectral_skin, m) {
  m.doc() = "Spectral Skin: skin reflectance, profiles and colour from four biophysical "
            "parameters (units: mm, 1/mm, nm). Same names as the C++ API and the `skin` CLI.";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);

  m.def("presets", [] {
    std::vector<std::string> names;
    for (const auto& p : presets()) names.push_back(p.name);
    return names;
  }, "Names of the paper's parameter sets.");

  m.def("parameters", [] {
    py::list table;
    for (const ParameterInfo& p : parameter_table())
      table.append(py::dict(
          py::arg("key") = p.key, py::arg("flag") = "--" + p.flag(),
          py::arg("symbol") = p.symbol.empty() ? py::object(py::none()) : py::cast(p.symbol),
          py::arg("unit") = p.unit, py::arg("min") = bound(p.min), py::arg("max") = bound(p.max),
          py::arg("min_exclusive") = p.min_open, py::arg("max_exclusive") = p.max_open,
          py::arg("default") = p.default_value(), py::arg("help") = p.help));
    return table;
  }, "The parameter table, as `skin parameters --format json`: key (the keyword), flag, the "
     "paper's symbol (also accepted as a keyword), unit, min/max (None = unbounded), "
     "min_exclusive/max_exclusive, default, help.");

  m.def("solvers", &transport::model_names, "Names of the transport models (solver=), the "
        "default first.");

  m.def(
      "spectrum",
      [](const std::string& preset, double lambda_min, double lambda_max, double lambda_step,
         const std::string& solver, const py::kwargs& kw) {
        const SkinSpectrum s = skin_spectrum(parameters(preset, kw),
                                             WavelengthGrid(lambda_min, lambda_max, lambda_step),
                                             transport::find_model(solver));
        py::dict d;
        d["parameters"] = parameters_dict(s.parameters);
        d["solver"] = s.solver;
        d["wavelength_nm"] = s.grid.values();
        d["R_d"] = s.R_d.values;
        d["epidermis"] = py::dict(py::arg("sigma_a") = s.epidermis_sigma_a.values,
                                  py::arg("sigma_s_prime") = s.epidermis_sigma_s_prime.values);
        d["dermis"] = py::dict(py::arg("sigma_a") = s.dermis_sigma_a.values,
                               py::arg("sigma_s_prime") = s.dermis_sigma_s_prime.values);
        d["color"] = color_dict(s.color);
        return d;
      },
      py::arg("preset") = "caucasian", py::arg("lambda_min") = 400.0,
      py::arg("lambda_max") = 700.0, py::arg("lambda_step") = 2.0,
      py::arg("solver") = std::string(transport::kDefaultModel),
      "R_d(lambda), the layers' sigma_a and sigma_s_prime [1/mm], the colour and the parameters "
      "used; any key of parameters() (melanin, melanin_blend, ...) or paper symbol (C_m, ...) "
      "as a keyword overrides the preset (None keeps it).");

  m.def(
      "rgb_profile",
      [](const std::string& preset, std::vector<double> r_mm, const std::string& solver,
         const py::kwargs& kw) {
        ProfileSolver ps(RadialGrid::from(std::move(r_mm)));
        const transport::Model& model = transport::find_model(solver);
        const SkinParameters p_skin = parameters(preset, kw);
        const RgbProfile p = skin_rgb_profile(p_skin, WavelengthGrid(), ps, model);
        py::dict d;
        d["parameters"] = parameters_dict(p_skin);
        d["validity"] = validity_dict(skin_validity(p_skin, WavelengthGrid(), model), model);
        d["r_mm"] = p.radii.r;
        d["R"] = py::dict(py::arg("r") = p.R[0], py::arg("g") = p.R[1], py::arg("b") = p.R[2]);
        d["R_d"] = std::vector<double>(p.R_d.begin(), p.R_d.end());
        return d;
      },
      py::arg("preset") = "caucasian", py::arg("r_mm"), py::arg("solver") = std::string(transport::kDefaultModel),
      "Radial profile R(r) [1/mm^2] per linear sRGB channel at the radii r_mm [mm] and the "
      "parameters used; parameter keywords as for spectrum().");

  m.def(
      "layers",
      [](const std::vector<std::map<std::string, double>>& layers, std::vector<double> r_mm,
         double eta_above, double eta_below, const std::string& solver) {
        LayerStack st;
        st.eta_above = eta_above;
        st.eta_below = eta_below;
        for (const auto& l : layers) {
          Layer x;
          for (const auto& [k, v] : l) {
            if (k == "sigma_a") x.sigma_a = v;
            else if (k == "sigma_s_prime") x.sigma_s_prime = v;
            else if (k == "thickness_mm" || k == "thickness") x.thickness = v;
            else if (k == "eta") x.eta = v;
            else if (k == "g") x.g = v;
            else throw InputError("unknown layer key '" + k + "'");
          }
          st.layers.push_back(x);
        }
        const transport::Model& model = transport::find_model(solver);
        const transport::Totals t = model.totals(st);
        py::dict d;
        d["R_d"] = t.R_d;
        d["T_d"] = t.T_d;
        d["R_specular"] = t.R_specular;
        std::vector<double> R;
        if (!r_mm.empty()) R = ProfileSolver(RadialGrid::from(r_mm)).profile(*model.response(st));
        const transport::Validity v = model.validity(st);
        // The profile's validity matters only where one is computed; the totals' always.
        d["validity"] = validity_dict(v, model, !v.totals || !r_mm.empty());
        d["profile"] = py::dict(py::arg("r_mm") = r_mm, py::arg("R") = R);
        return d;
      },
      py::arg("layers"), py::arg("r_mm") = std::vector<double>{}, py::arg("eta_above") = 1.0,
      py::arg("eta_below") = 1.0, py::arg("solver") = std::string(transport::kDefaultModel),
      "R_d, T_d (per power that entered) and R(r) of a layer stack given as a list of dicts with "
      "sigma_a, sigma_s_prime [1/mm], thickness [mm] (absent = semi-infinite), eta, g.");
}
