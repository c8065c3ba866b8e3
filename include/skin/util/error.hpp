#pragma once
// User-facing input errors. A user error throws skin::util::InputError with one line naming the
// parameter, its value and the allowed range; the command line reports it once and exits 2.
// Broken invariants (programmer errors) use SKIN_ASSERT, which aborts with both operands.
#include <stdexcept>
#include <string>
#include <string_view>

namespace skin::util {

// Its message is one line by construction: control characters (a newline, a carriage return,
// bytes of the user's file quoted by a decoder's message) are shown as \xNN escapes.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message);
  explicit InputError(const char* message) : InputError(std::string(message)) {}
};

// Text shown as one line: control characters (below 0x20, and 0x7f) as \xNN escapes.
std::string one_line(std::string_view text);

// Formats a double the way messages show it (shortest round-trip form).
std::string format_number(double v);

// Each throws InputError("<name> = <value> is out of range: must be ...") on failure; NaN and
// infinities always fail. `unit` (for example "mm") is appended to the numbers when non-empty.
void require_finite(std::string_view name, double value);
void require_in_range(std::string_view name, double value, double lo, double hi,
                      std::string_view unit = "");
void require_positive(std::string_view name, double value, std::string_view unit = "");
void require_non_negative(std::string_view name, double value, std::string_view unit = "");

[[noreturn]] void assertion_failed(const char* expr, const char* file, int line,
                                   const std::string& detail);

}  // namespace skin::util

// Invariant check kept in release builds (cheap checks only, never in hot loops).
#define SKIN_ASSERT(cond, detail)                                                  \
  do {                                                                             \
    if (!(cond)) ::skin::util::assertion_failed(#cond, __FILE__, __LINE__, (detail));  \
  } while (0)
