#pragma once
// Floating-point text conversions with std::from_chars / std::to_chars semantics, also where the
// standard library lacks them for double (libc++ 14, the one of Debian's Emscripten 3.1.6 that
// builds the web page, web/): there the fallbacks below, built on strtod and snprintf, take
// over. Both are always compiled so that tests compare them with the standard library's.
#include <charconv>
#include <string>

namespace skin::util {

// As std::from_chars(first, last, value) in the general format: optional '-', decimal digits
// with an optional point and exponent, or inf/infinity/nan (no '+', no whitespace, no hex).
std::from_chars_result from_chars(const char* first, const char* last, double& value);
// As std::to_chars(first, last, value) with no format: the shortest text that reads back to
// `value`, fixed or scientific, whichever is shorter (fixed on a tie).
std::string to_chars_shortest(double value);

namespace detail {
std::from_chars_result from_chars_fallback(const char* first, const char* last, double& value);
std::string to_chars_shortest_fallback(double value);
}  // namespace detail

}  // namespace skin::util
