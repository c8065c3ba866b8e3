// The table of frequency-domain skin profiles (data/skin_stack_profiles.csv, written by
// skin tabulate-skin-profiles): skin::transport::accurate::SkinStackTable::parse, then the profile of a stack
// inside it (two layers and, if it has half-space nodes, a half-space). Invariants: a table that parses, written out (to_csv) and parsed again, writes the
// same text; the profile of a stack it covers is finite and >= 0 at every radius.
#include <cmath>

#include "fuzz_support.hpp"
#include "skin/transport/skin_stack_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using skin::transport::accurate::SkinStackTable;
  namespace fuzz = skin::fuzz;
  SkinStackTable table;
  if (!fuzz::accepts([&] { table = SkinStackTable::parse(fuzz::text(data, size), "fuzz.csv"); })) return 0;
  const std::string csv = table.to_csv();
  SkinStackTable again;
  if (!fuzz::accepts([&] { again = SkinStackTable::parse(csv, "re-written"); }))
    fuzz::finding("the re-written table does not parse");
  if (again.to_csv() != csv) fuzz::finding("the re-written table reads differently");
  // A stack in the middle of the table's ranges (s = 5 /mm), with its own geometry.
  const double s = 5.0, tau = std::sqrt(table.tau.front() * table.tau.back());
  const double a_e = std::sqrt(table.a_e.front() * table.a_e.back());
  const double a_d = std::sqrt(table.a_d.front() * table.a_d.back());
  skin::physics::LayerStack stack;
  stack.layers = {skin::physics::Layer{a_e * s, s, tau / s, table.eta, table.g},
                  skin::physics::Layer{a_d * s, table.dermis_ratio * s, skin::physics::kInfinity, table.eta, table.g}};
  if (!(table.eta >= 1 && table.eta <= 3 && std::abs(table.g) < 1 && table.dermis_ratio > 0)) return 0;
  auto check = [](const skin::transport::accurate::SkinStackProfile& profile) {
    for (double r = 0; r < 100; r = r == 0 ? 1e-6 : r * 1.7) {
      const double v = profile(r);
      if (!std::isfinite(v) || v < 0) fuzz::finding("the profile of a covered stack is not finite and >= 0");
    }
  };
  if (table.gap(stack).empty()) check(skin::transport::accurate::SkinStackProfile(table, stack, 0.5));
  // The half-space in the middle of its range, when the table has one.
  if (!table.a_h.empty()) {
    skin::physics::LayerStack half;
    half.layers = {skin::physics::Layer{std::sqrt(table.a_h.front() * table.a_h.back()) * s, s, skin::physics::kInfinity, table.eta, table.g}};
    if (table.gap(half).empty()) check(skin::transport::accurate::SkinStackProfile(table, half, 0.5));
  }
  return 0;
}
