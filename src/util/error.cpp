#include "skin/util/error.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "skin/util/charconv.hpp"

namespace skin::util {

std::string one_line(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char esc[5];
      std::snprintf(esc, sizeof esc, "\\x%02x", u);
      out += esc;
    } else {
      out += c;
    }
  }
  return out;
}

InputError::InputError(const std::string& message) : std::runtime_error(one_line(message)) {}

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return to_chars_shortest(v);
}

namespace {
std::string with_unit(double v, std::string_view unit) {
  std::string s = format_number(v);
  if (!unit.empty()) {
    s += ' ';
    s += unit;
  }
  return s;
}
[[noreturn]] void fail(std::string_view name, double value, std::string_view unit,
                       const std::string& allowed) {
  throw InputError(std::string(name) + " = " + with_unit(value, unit) +
                   " is out of range: " + allowed);
}
}  // namespace

void require_finite(std::string_view name, double value) {
  if (!std::isfinite(value)) fail(name, value, "", "must be a finite number");
}

void require_in_range(std::string_view name, double value, double lo, double hi,
                      std::string_view unit) {
  if (!(value >= lo && value <= hi))
    fail(name, value, unit, "allowed range is [" + with_unit(lo, unit) + ", " +
                                with_unit(hi, unit) + "]");
}

void require_positive(std::string_view name, double value, std::string_view unit) {
  if (!(value > 0) || !std::isfinite(value))
    fail(name, value, unit, "must be a finite number > 0");
}

void require_non_negative(std::string_view name, double value, std::string_view unit) {
  if (!(value >= 0) || !std::isfinite(value))
    fail(name, value, unit, "must be a finite number >= 0");
}

void assertion_failed(const char* expr, const char* file, int line, const std::string& detail) {
  std::fprintf(stderr, "skin: internal error: %s failed at %s:%d: %s\n", expr, file, line,
               detail.c_str());
  std::abort();
}

}  // namespace skin::util
