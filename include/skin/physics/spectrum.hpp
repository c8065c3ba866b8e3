#pragma once
// Wavelength grids and spectra. A spectrum on a grid (Spectrum) is kept apart from a continuous
// function of wavelength (TabulatedFunction): code can only combine spectra on the same grid.
// Wavelengths in nm.
#include <array>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace skin::physics {

// Evenly spaced wavelengths lambda_min, lambda_min + step, ..., up to lambda_max inclusive.
class WavelengthGrid {
 public:
  // The paper's sampling: 400-700 nm every 2 nm (151 samples).
  WavelengthGrid() : WavelengthGrid(400.0, 700.0, 2.0) {}
  // Throws InputError unless 0 < lambda_min <= lambda_max, step > 0 and (max - min) / step is a
  // whole number (within 1e-9), so that both ends are sampled.
  WavelengthGrid(double lambda_min, double lambda_max, double step);

  std::size_t size() const { return n_; }
  double operator[](std::size_t i) const { return lambda_min_ + step_ * static_cast<double>(i); }
  double lambda_min() const { return lambda_min_; }
  double lambda_max() const { return lambda_max_; }
  double step() const { return step_; }
  std::vector<double> values() const;

  bool operator==(const WavelengthGrid& o) const = default;

 private:
  double lambda_min_, lambda_max_, step_;
  std::size_t n_;
};

std::ostream& operator<<(std::ostream& os, const WavelengthGrid& g);

// Values of some quantity on a wavelength grid.
struct Spectrum {
  WavelengthGrid grid;
  std::vector<double> values;

  Spectrum() = default;
  explicit Spectrum(const WavelengthGrid& g, double fill = 0.0)
      : grid(g), values(g.size(), fill) {}
  std::size_t size() const { return values.size(); }
  double operator[](std::size_t i) const { return values[i]; }
  double& operator[](std::size_t i) { return values[i]; }
};

std::ostream& operator<<(std::ostream& os, const Spectrum& s);

// Per-wavelength weights of three linear colour channels: channel c = sum_i weights[i][c] x
// spectrum[i]. The colour module gives linear sRGB's (Colorimetry::srgb_weights); the transport
// module applies them to profiles (ProfileSolver::rgb).
using ChannelWeights = std::vector<std::array<double, 3>>;

// A function of one variable given by a table, linearly interpolated. Outside the table it
// either throws (Outside::error: the data must cover what is asked) or returns 0
// (Outside::zero: for colour-matching functions, which are zero outside their range).
class TabulatedFunction {
 public:
  enum class Outside { error, zero };
  TabulatedFunction() = default;
  // x strictly increasing, same size as y, at least two points.
  TabulatedFunction(std::vector<double> x, std::vector<double> y, std::string name,
                    Outside outside = Outside::error);
  double operator()(double x) const;
  Spectrum sample(const WavelengthGrid& g) const;
  double x_min() const { return x_.front(); }
  double x_max() const { return x_.back(); }
  const std::string& name() const { return name_; }
  const std::vector<double>& x() const { return x_; }
  const std::vector<double>& y() const { return y_; }

 private:
  std::vector<double> x_, y_;
  std::string name_;
  Outside outside_ = Outside::error;
};

}  // namespace skin::physics
