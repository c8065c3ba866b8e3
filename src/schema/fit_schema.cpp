// The schema of skin fit --spectrum (fit_schema.hpp).
#include "fit_schema.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "skin/util/error.hpp"

namespace skin::schema {

namespace {
json uncertainty_json(const fit::FitResult& r) {
  json j = json::object();
  for (std::size_t i = 0; i < r.free.size(); ++i) {
    const double u = r.uncertainty[i];
    j[std::string(fit::key(r.free[i]))] = std::isfinite(u) ? json(u) : json(nullptr);
  }
  return j;
}
}  // namespace

Result spectrum_fit_result(const fit::MeasuredSpectrum& m, const fit::FitResult& r,
                           const std::string& solver, bool includes_specular, double port_radius,
                           double beam_radius) {
  Result result;
  {
    json j;
    j["input"] = m.name;
    j["solver"] = solver;
    j["includes_specular"] = includes_specular;
    j["port_radius"] = port_radius > 0 ? json(port_radius) : json(nullptr);
    j["beam_radius"] = port_radius > 0 ? json(beam_radius) : json(nullptr);
    json free = json::array();
    for (auto p : r.free) free.push_back(std::string(fit::key(p)));
    j["free"] = free;
    j["parameters"] = to_json(r.parameters);
    j["uncertainty"] = uncertainty_json(r);
    json at_bound = json::object();
    for (std::size_t i = 0; i < r.free.size(); ++i) at_bound[std::string(fit::key(r.free[i]))] = bool(r.at_bound[i]);
    j["at_bound"] = at_bound;
    j["model"] = std::string(fit::name(r.fit_model));
    j["rms"] = r.rms;
    // How far the spectrum lies outside the model's gamut: the RMS (outside at or above
    // fit::kGoodFitRms) and the colour difference of measured and fitted samples.
    j["delta_e_2000"] = r.delta_e;
    j["outside_gamut"] = r.outside_gamut;
    j["outside_gamut_rms"] = fit::kGoodFitRms;
    j["specular"] = r.specular;
    j["iterations"] = r.iterations;
    j["starts"] = r.starts;
    j["fitted"] = {{"wavelength_nm", r.wavelength_nm}, {"measured", r.measured}, {"R", r.fitted}};
    result.document = j;
  }
  {
    std::vector<std::string> h;
    std::vector<std::vector<double>> c;
    for (std::size_t i = 0; i < r.free.size(); ++i) {
      h.push_back(std::string(fit::key(r.free[i])));
      c.push_back({fit::get(r.parameters, r.free[i])});
      h.push_back("uncertainty." + std::string(fit::key(r.free[i])));
      c.push_back({r.uncertainty[i]});
    }
    h.push_back("rms");
    c.push_back({r.rms});
    for (std::size_t k = 0; k < h.size(); ++k) result.columns.push_back({h[k], c[k], {}});
  }
  {
    std::ostringstream os;
    os << "fit of " << m.name << " (" << r.wavelength_nm.size() << " samples, "
       << r.wavelength_nm.front() << "-" << r.wavelength_nm.back() << " nm, solver " << solver << ")\n";
    if (port_radius > 0)
      os << "  measured through a port of radius " << port_radius << " mm, the beam "
         << (beam_radius > 0 ? "over a disc of radius " + util::format_number(beam_radius) + " mm" : std::string("a pencil"))
         << " at its centre\n";
    for (std::size_t i = 0; i < r.free.size(); ++i) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "  %-22s %12.6g  +- %-10.3g%s\n", std::string(fit::key(r.free[i])).c_str(),
                    fit::get(r.parameters, r.free[i]), r.uncertainty[i], r.at_bound[i] ? "  (at bound)" : "");
      os << buf;
    }
    if (includes_specular) os << "  specular term rho_s F    " << r.specular << "\n";
    os << "  RMS residual             " << r.rms << "\n";
    if (r.fit_model == fit::FitModel::extended || r.outside_gamut) {
      const auto bound = std::count(r.at_bound.begin(), r.at_bound.end(), true);
      char buf[200];
      std::snprintf(buf, sizeof buf, "  model %s: colour dE2000 %.3g, %d parameter(s) at a bound%s\n",
                    std::string(fit::name(r.fit_model)).c_str(), r.delta_e, static_cast<int>(bound),
                    r.outside_gamut ? ", outside the model's gamut (RMS >= 0.02)" : "");
      os << buf;
    }
    result.table = os.str();
  }
  return result;
}

}  // namespace skin::schema
