#pragma once
// The CIE illuminants, as data (data/d65.csv, data/cie_illuminants.csv; CIE 015:2018 tables, see
// docs/illuminants.md): relative spectral power, linearly interpolated between the table's
// wavelengths (A: its closed form) and zero outside them. Names as CIE 015:2018 spells them: D65 (the default), D50,
// A, FL2, FL7, FL11, LED-B1 ... LED-V2.
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "skin/physics/spectrum.hpp"

namespace skin::color {

// The illuminant a colour is computed under when none is named (skin color, Python's color(),
// the web page, Colorimetry's default).
inline constexpr std::string_view kDefaultIlluminant = "D65";
// The white point of sRGB (IEC 61966-2-1): the white that linear sRGB is referred to, the target of
// the chromatic adaptation, and the light an RGB renderer's colours are taken under. Another
// concept than the default illuminant, though both are D65.
inline constexpr std::string_view kSrgbWhite = "D65";

// Illuminant A's closed form (ISO/CIE 11664-2:2022 eq. 1), which defines it: Planck's law with
// c2 = 1.435e-2 m K at T = 2848 K (2856 K on today's c2 = 1.4388e-2 m K), 100 at 560 nm.
double illuminant_a(double lambda_nm);

class Illuminant {
 public:
  using ClosedForm = double (*)(double lambda_nm);
  // `closed_form`, if given, defines the illuminant over the table's range (A); the table is then
  // the standard's rounding of it.
  Illuminant(std::string name, std::string description, physics::TabulatedFunction table,
             ClosedForm closed_form = nullptr);
  const std::string& name() const { return name_; }
  const std::string& description() const { return description_; }  // e.g. "daylight, 6504 K"
  // Relative spectral power at `lambda_nm` [nm] (A and the D series are 100 at 560 nm): the
  // closed form, or the table linearly interpolated; 0 outside the table's range.
  double operator()(double lambda_nm) const;
  physics::Spectrum sample(const physics::WavelengthGrid& grid) const;
  const physics::TabulatedFunction& table() const { return table_; }
  bool has_closed_form() const { return closed_form_ != nullptr; }

 private:
  std::string name_, description_;
  physics::TabulatedFunction table_;
  ClosedForm closed_form_ = nullptr;
};
std::ostream& operator<<(std::ostream& os, const Illuminant& i);

// Every illuminant, D65 first, then in the order of CIE 015:2018.
std::vector<std::string> illuminant_names();
// By name, ignoring case ("d65" finds D65). Throws InputError("illuminant = 'X' is unknown: must
// be one of D65, D50, ...") for another name.
const Illuminant& find_illuminant(std::string_view name);

}  // namespace skin::color
