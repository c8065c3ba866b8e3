// The text conversions of skin/util/charconv.hpp: the fallbacks (the web build's, where the
// standard library lacks floating-point from_chars / to_chars) give exactly what libstdc++'s
// std::from_chars / std::to_chars give, on random doubles of every magnitude and on edge texts.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "skin/util/charconv.hpp"
#include "skin/util/random.hpp"

namespace skin::util {

namespace {

std::string std_shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

TEST(Charconv, ShortestTextAsToCharsOnRandomBitPatterns) {
  Xoshiro256Plus rng(20261201, 0);
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    const double v = std::bit_cast<double>(rng.next_u64());
    if (!std::isfinite(v)) continue;
    ASSERT_EQ(detail::to_chars_shortest_fallback(v), std_shortest(v)) << v;
    ++checked;
  }
  EXPECT_GT(checked, 190000);
}

TEST(Charconv, ShortestTextAsToCharsOnTypicalValues) {
  // Values of the kind the project prints: round decimals, ranges, their neighbours.
  for (double v : {0.0, -0.0, 1.0, 0.1, 0.005, 0.7, 1e-6, 1e-4, 1e-5, 100000.0, 123456.0,
                   1e21, 1e22, 1234567.0, 0.30000000000000004, 2.5e-7, 1000.0, 1e15, 1e16,
                   std::numeric_limits<double>::min(), std::numeric_limits<double>::max(),
                   std::numeric_limits<double>::denorm_min(), 5e-324, 9007199254740993.0}) {
    EXPECT_EQ(detail::to_chars_shortest_fallback(v), std_shortest(v)) << v;
    EXPECT_EQ(detail::to_chars_shortest_fallback(-v), std_shortest(-v)) << v;
    EXPECT_EQ(detail::to_chars_shortest_fallback(std::nextafter(v, 2 * v + 1)),
              std_shortest(std::nextafter(v, 2 * v + 1))) << v;
  }
  EXPECT_EQ(detail::to_chars_shortest_fallback(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(detail::to_chars_shortest_fallback(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(detail::to_chars_shortest_fallback(std::nan("")), "nan");
}

TEST(Charconv, ParsesAsFromChars) {
  for (const std::string text :
       {"0", "-0", "1", "0.25", ".5", "5.", "-3.75e-3", "1e308", "1e309", "-1e309", "1e-400",
        "4.9e-324", "inf", "-inf", "Infinity", "nan", "NaN", "+1", " 1", "", "-", ".", "e5", "1e",
        "1e+", "1.5abc", "0x1p3", "-0x10", "12,3", "1..2", "--1", "1e+05", "0.0001"}) {
    double a = -7, b = -7;
    const auto ra = std::from_chars(text.data(), text.data() + text.size(), a);
    const auto rb = detail::from_chars_fallback(text.data(), text.data() + text.size(), b);
    EXPECT_EQ(rb.ec, ra.ec) << "'" << text << "'";
    EXPECT_EQ(rb.ptr - text.data(), ra.ptr - text.data()) << "'" << text << "'";
    if (ra.ec == std::errc()) {
      if (std::isnan(a)) EXPECT_TRUE(std::isnan(b)) << text;
      else EXPECT_EQ(std::bit_cast<std::uint64_t>(b), std::bit_cast<std::uint64_t>(a)) << text;
    }
  }
}

TEST(Charconv, ParsesShortestTextBackExactly) {
  Xoshiro256Plus rng(7, 0);
  for (int i = 0; i < 50000; ++i) {
    const double v = std::bit_cast<double>(rng.next_u64());
    if (!std::isfinite(v)) continue;
    const std::string t = std_shortest(v);
    double back = 0;
    const auto r = detail::from_chars_fallback(t.data(), t.data() + t.size(), back);
    ASSERT_EQ(r.ec, std::errc()) << t;
    ASSERT_EQ(back, v) << t;
  }
}

}  // namespace
}  // namespace skin::util
