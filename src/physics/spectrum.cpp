#include "skin/physics/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/util/error.hpp"

namespace skin::physics {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::require_positive;

WavelengthGrid::WavelengthGrid(double lambda_min, double lambda_max, double step)
    : lambda_min_(lambda_min), lambda_max_(lambda_max), step_(step) {
  require_positive("lambda_min", lambda_min, "nm");
  require_positive("lambda_max", lambda_max, "nm");
  require_positive("lambda_step", step, "nm");
  if (lambda_max < lambda_min)
    throw InputError("lambda_max = " + format_number(lambda_max) +
                     " nm is out of range: must be >= lambda_min = " +
                     format_number(lambda_min) + " nm");
  const double intervals = (lambda_max - lambda_min) / step;
  const double whole = std::round(intervals);
  if (std::abs(intervals - whole) > 1e-9 * std::max(1.0, whole))
    throw InputError("lambda_step = " + format_number(step) +
                     " nm is out of range: (lambda_max - lambda_min) / lambda_step must be a "
                     "whole number so that both ends are sampled");
  if (whole > 1e6)
    throw InputError("lambda_step = " + format_number(step) +
                     " nm is out of range: at most 1000000 wavelengths");
  n_ = static_cast<std::size_t>(whole) + 1;
}

std::vector<double> WavelengthGrid::values() const {
  std::vector<double> v(n_);
  for (std::size_t i = 0; i < n_; ++i) v[i] = (*this)[i];
  return v;
}

std::ostream& operator<<(std::ostream& os, const WavelengthGrid& g) {
  return os << "WavelengthGrid[" << g.lambda_min() << ".." << g.lambda_max() << " nm step "
            << g.step() << ", " << g.size() << " samples]";
}

std::ostream& operator<<(std::ostream& os, const Spectrum& s) {
  os << "Spectrum{" << s.grid << ":";
  const std::size_t n = s.values.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (n > 12 && i == 6) {
      os << " ...";
      i = n - 6;
    }
    os << ' ' << s.values[i];
  }
  return os << '}';
}

TabulatedFunction::TabulatedFunction(std::vector<double> x, std::vector<double> y,
                                     std::string name, Outside outside)
    : x_(std::move(x)), y_(std::move(y)), name_(std::move(name)), outside_(outside) {
  if (x_.size() != y_.size() || x_.size() < 2)
    throw InputError(name_ + ": a table needs at least two (x, y) rows of equal length");
  for (std::size_t i = 1; i < x_.size(); ++i)
    if (!(x_[i] > x_[i - 1]))
      throw InputError(name_ + ": wavelengths must increase strictly (row " + std::to_string(i + 1) +
                       ": " + format_number(x_[i]) + " after " + format_number(x_[i - 1]) + ")");
}

double TabulatedFunction::operator()(double x) const {
  if (!(x >= x_.front() && x <= x_.back())) {
    if (outside_ == Outside::zero && !std::isnan(x)) return 0.0;
    throw InputError(name_ + ": wavelength " + format_number(x) + " nm is outside the table [" +
                     format_number(x_.front()) + ", " + format_number(x_.back()) + "] nm");
  }
  auto it = std::upper_bound(x_.begin(), x_.end(), x);
  std::size_t i = static_cast<std::size_t>(it - x_.begin());
  if (i >= x_.size()) return y_.back();
  const std::size_t j = i - 1;
  const double t = (x - x_[j]) / (x_[i] - x_[j]);
  return y_[j] + t * (y_[i] - y_[j]);
}

Spectrum TabulatedFunction::sample(const WavelengthGrid& g) const {
  Spectrum s(g);
  for (std::size_t i = 0; i < g.size(); ++i) s[i] = (*this)(g[i]);
  return s;
}

}  // namespace skin::physics
