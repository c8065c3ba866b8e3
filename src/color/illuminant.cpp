#include "skin/color/illuminant.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <ostream>

#include "skin/util/error.hpp"
#include "skin/util/table.hpp"

namespace skin::color {

using skin::util::InputError;
using skin::util::Table;

using skin::physics::Spectrum;
using skin::physics::TabulatedFunction;
using skin::physics::WavelengthGrid;

double illuminant_a(double l) {
  constexpr double c2 = 1.435e7, T = 2848.0;  // [nm K], [K]
  return 100.0 * std::pow(560.0 / l, 5) * std::expm1(c2 / (T * 560.0)) / std::expm1(c2 / (T * l));
}

Illuminant::Illuminant(std::string name, std::string description, TabulatedFunction table,
                       ClosedForm closed_form)
    : name_(std::move(name)), description_(std::move(description)), table_(std::move(table)),
      closed_form_(closed_form) {}

double Illuminant::operator()(double l) const {
  if (!closed_form_) return table_(l);
  return l >= table_.x_min() && l <= table_.x_max() ? closed_form_(l) : 0.0;
}

Spectrum Illuminant::sample(const WavelengthGrid& grid) const {
  Spectrum s(grid);
  for (std::size_t i = 0; i < grid.size(); ++i) s[i] = (*this)(grid[i]);
  return s;
}

std::ostream& operator<<(std::ostream& os, const Illuminant& i) {
  return os << "Illuminant(" << i.name() << ", " << i.description() << ", " << i.table().x_min()
            << "-" << i.table().x_max() << " nm" << (i.has_closed_form() ? ", closed form" : "") << ')';
}

namespace {

struct Entry {
  const char* name;
  const char* description;
};
// The column of data/cie_illuminants.csv of each illuminant (D65 has its own 1 nm file), in the
// order of CIE 015:2018; descriptions from the standard (correlated colour temperatures).
constexpr Entry kTable[] = {
    {"D50", "daylight, 5003 K"},
    {"A", "incandescent (Planckian), 2856 K"},
    {"FL2", "fluorescent, standard cool white, 4230 K"},
    {"FL7", "fluorescent, broad-band D65 simulator, 6500 K"},
    {"FL11", "fluorescent, narrow three-band, 4000 K"},
    {"LED-B1", "LED, phosphor-converted blue, 2733 K"},
    {"LED-B2", "LED, phosphor-converted blue, 2998 K"},
    {"LED-B3", "LED, phosphor-converted blue, 4103 K"},
    {"LED-B4", "LED, phosphor-converted blue, 5109 K"},
    {"LED-B5", "LED, phosphor-converted blue, 6598 K"},
    {"LED-BH1", "LED, hybrid blue and red, 2851 K"},
    {"LED-RGB1", "LED, mixed red, green and blue, 2840 K"},
    {"LED-V1", "LED, phosphor-converted violet, 2724 K"},
    {"LED-V2", "LED, phosphor-converted violet, 4070 K"},
};

std::vector<Illuminant> load() {
  std::vector<Illuminant> out;
  {
    const Table& t = util::data::embedded_table("d65.csv");
    out.emplace_back("D65", "daylight, 6504 K",
                     TabulatedFunction(t.data[0], t.data[1], "data/d65.csv",
                                       TabulatedFunction::Outside::zero));
  }
  const Table& t = util::data::embedded_table("cie_illuminants.csv");
  for (const Entry& e : kTable) {
    // The rows where the standard gives a value (an empty field reads as NaN).
    const std::vector<double>& y = t.data[t.column(e.name)];
    std::vector<double> xs, ys;
    for (std::size_t i = 0; i < t.rows(); ++i)
      if (!std::isnan(y[i])) {
        xs.push_back(t.data[0][i]);
        ys.push_back(y[i]);
      }
    out.emplace_back(e.name, e.description,
                     TabulatedFunction(std::move(xs), std::move(ys),
                                       std::string("data/cie_illuminants.csv:") + e.name,
                                       TabulatedFunction::Outside::zero),
                     std::string_view(e.name) == "A" ? &illuminant_a : nullptr);
  }
  return out;
}

const std::vector<Illuminant>& all() {
  static const std::vector<Illuminant> v = load();
  return v;
}

bool same_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

}  // namespace

std::vector<std::string> illuminant_names() {
  std::vector<std::string> names;
  for (const Illuminant& i : all()) names.push_back(i.name());
  return names;
}

const Illuminant& find_illuminant(std::string_view name) {
  for (const Illuminant& i : all())
    if (same_ignoring_case(i.name(), name)) return i;
  // The names before CIE 015:2018 (F2, F7, F11) for its FL2, FL7, FL11.
  if (name.size() >= 2 && (name[0] == 'F' || name[0] == 'f') && name[1] >= '0' && name[1] <= '9')
    for (const Illuminant& i : all())
      if (same_ignoring_case(i.name(), "FL" + std::string(name.substr(1)))) return i;
  std::string allowed;
  for (const Illuminant& i : all()) allowed += (allowed.empty() ? "" : ", ") + i.name();
  throw InputError("illuminant = '" + std::string(name) + "' is unknown: must be one of " + allowed +
                   " (F2, F7, F11 name FL2, FL7, FL11)");
}

}  // namespace skin::color
