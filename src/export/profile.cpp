// The radial profile R(r) itself per channel, as a table: CSV, JSON and a 1-D EXR
// (docs/export.md, "Real-time and tables").
#include <cmath>
#include <sstream>

#include "report.hpp"

namespace skin::exporting::detail {

namespace {

Export write(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  const double scale = ctx.scale();
  Export e;
  e.report = fit_report(ctx, "the profile itself (no target model)", ref.R_d, ref.R);
  // A table on the reference grid (logarithmic), values per unit^2.
  const std::size_t J = ref.radii.size();
  std::array<double, 3> check{};
  for (int c = 0; c < 3; ++c) check[c] = area_integral(ref.radii, ref.R[c]);
  std::ostringstream csv;
  const std::string u(unit_name(unit));
  csv << "# Spectral Skin radial profile R(r) per linear Rec.709 channel (docs/export.md).\n"
      << "# units: r in " << u << ", R in 1/" << u << "^2; normalisation 2 pi int R(r) r dr = R_d\n"
      << "# R_d: " << triple(ref.R_d, ",") << "\n"
      << "# table_integral: " << num(check[0]) << "," << num(check[1]) << "," << num(check[2]) << "\n";
  csv << "r_" << u << ",R_r,R_g,R_b\n";
  json j = document_head("Spectral Skin radial profile", o);
  j["units"] = {{"r", u}, {"R", "1/" + u + "^2"}};
  j["R_d"] = vec(ref.R_d);
  j["normalisation"] = {{"definition", "2 pi int R(r) r dr = R_d"},
                        {"table_integral", {check[0], check[1], check[2]}}};
  std::vector<double> r(J);
  std::array<std::vector<double>, 3> R;
  image::Planes planes{static_cast<int>(J), 1, {"r", "R", "G", "B"}, {}};
  planes.values.assign(4, std::vector<float>(J));
  for (std::size_t i = 0; i < J; ++i) {
    r[i] = ref.radii.r[i] * scale;
    csv << num(r[i]);
    planes.values[0][i] = static_cast<float>(r[i]);
    for (int c = 0; c < 3; ++c) {
      const double v = ref.R[c][i] / (scale * scale);
      R[c].push_back(v);
      csv << "," << num(v);
      planes.values[1 + c][i] = static_cast<float>(v);
    }
    csv << "\n";
  }
  j["r"] = r;
  j["R"] = {{"r", R[0]}, {"g", R[1]}, {"b", R[2]}};
  e.files.push_back({"", csv.str(), false});
  e.files.push_back({".json", rounded(j).dump(1) + "\n", false});
  ImageFile exr{".exr", std::move(planes), {}, false};
  e.images.push_back(std::move(exr));
  for (int c = 0; c < 3; ++c)
    if (std::abs(check[c] / ref.R_d[c] - 1.0) > 0.01)
      e.report.notes.push_back("the table integrates to R_d only within " +
                               num(100 * std::abs(check[c] / ref.R_d[c] - 1.0)) + " % in channel " +
                               "RGB"[c]);
  return e;
}

}  // namespace

TargetSpec profile_target() {
  return {"profile", "the radial profile R(r) per channel as a table (CSV, JSON, 1-D EXR)", ".csv",
          Unit::mm, write};
}

}  // namespace skin::exporting::detail
