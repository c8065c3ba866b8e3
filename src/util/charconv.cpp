#include "skin/util/charconv.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace skin::util {

// libstdc++ has both conversions for double since GCC 11 and announces them with
// __cpp_lib_to_chars; libc++ 14 declares them deleted and does not.
#if defined(__cpp_lib_to_chars)
std::from_chars_result from_chars(const char* first, const char* last, double& value) {
  return std::from_chars(first, last, value);
}
std::string to_chars_shortest(double value) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, res.ptr);
}
#else
std::from_chars_result from_chars(const char* first, const char* last, double& value) {
  return detail::from_chars_fallback(first, last, value);
}
std::string to_chars_shortest(double value) { return detail::to_chars_shortest_fallback(value); }
#endif

namespace detail {

std::from_chars_result from_chars_fallback(const char* first, const char* last, double& value) {
  const char* p = first;
  if (p != last && *p == '-') ++p;
  // The general format's first character: a digit, a point, or the i/n of inf/nan. strtod would
  // also take '+', whitespace and hexadecimal; from_chars takes none of them.
  const bool ok_start = p != last && (std::isdigit(static_cast<unsigned char>(*p)) || *p == '.' ||
                                      std::strchr("iInN", *p) != nullptr);
  if (!ok_start) return {first, std::errc::invalid_argument};
  std::string text(first, last);
  const std::size_t at = static_cast<std::size_t>(p - first);
  if (text.size() > at + 1 && text[at] == '0' && (text[at + 1] == 'x' || text[at + 1] == 'X'))
    text.resize(at + 1);  // "0x1p3": from_chars reads the "0" only
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str()) return {first, std::errc::invalid_argument};
  const char* stop = first + (end - text.c_str());
  // strtod reports ERANGE for subnormal results too; from_chars only for overflow and for a
  // nonzero text that rounds to zero.
  if (errno == ERANGE && (v == 0 || std::isinf(v))) return {stop, std::errc::result_out_of_range};
  value = v;
  return {stop, std::errc()};
}

std::string to_chars_shortest_fallback(double value) {
  if (std::isnan(value)) return std::signbit(value) ? "-nan" : "nan";
  if (std::isinf(value)) return value < 0 ? "-inf" : "inf";
  if (value == 0) return std::signbit(value) ? "-0" : "0";
  // The shortest correctly rounded significand that reads back to the value.
  char buf[64];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*e", digits - 1, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  // buf: [-]d[.ddd]e±XX; its digits (trailing zeros dropped) and decimal exponent.
  const std::string s = buf;
  const bool negative = s[0] == '-';
  const std::size_t e = s.find('e');
  std::string digits;
  for (std::size_t i = negative ? 1 : 0; i < e; ++i)
    if (s[i] != '.') digits += s[i];
  while (digits.size() > 1 && digits.back() == '0') digits.pop_back();
  const int exponent = std::atoi(s.c_str() + e + 1);
  const int n = static_cast<int>(digits.size());
  // Scientific, as printf's %e writes it (at least two exponent digits).
  char exp_text[16];
  std::snprintf(exp_text, sizeof exp_text, "e%c%02d", exponent < 0 ? '-' : '+', std::abs(exponent));
  std::string scientific = digits.substr(0, 1);
  if (n > 1) scientific += '.' + digits.substr(1);
  scientific += exp_text;
  std::string fixed;
  if (exponent >= n - 1) {
    // An integer: to_chars writes its exact digits, as %.0f does (as long as the shortest ones).
    char integer[320];  // DBL_MAX has 309 digits
    std::snprintf(integer, sizeof integer, "%.0f", std::fabs(value));
    fixed = integer;
  } else if (exponent >= 0) {
    fixed = digits.substr(0, static_cast<std::size_t>(exponent + 1)) + "." +
            digits.substr(static_cast<std::size_t>(exponent + 1));
  } else {
    fixed = "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
  }
  std::string text = negative ? "-" : "";
  text += fixed.size() <= scientific.size() ? fixed : scientific;
  return text;
}

}  // namespace detail
}  // namespace skin::util
