// The table of frequency-domain skin profiles (data/skin_stack_profiles.csv, written by
// skin tabulate-skin-profiles): skin::transport::accurate::SkinStackTable::parse, then the profile of a stack
// inside it (two layers and, if it has half-space nodes, a half-space). Invariants: a table that parses, written out (to_csv) and parsed again, writes the
// same text; the profile of a stack it covers is finite and >= 0 at every radius. The same input
// is also read as the table's offsets and their cross terms, and as the half-space table
// (data/half_space_profiles.csv) (below).
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "skin/transport/half_space_table.hpp"
#include "skin/transport/skin_stack_table.hpp"

namespace {
// A covered stack's profile: finite and >= 0 at every radius, or a finding named `what`.
void check_profile(const skin::transport::accurate::SkinStackProfile& profile, const char* what) {
  for (double r = 0; r < 100; r = r == 0 ? 1e-6 : r * 1.7) {
    const double v = profile(r);
    if (!std::isfinite(v) || v < 0) skin::fuzz::finding(what);
  }
}
// The input parsed as a T (a table kind with parse() and to_csv()), or false when refused; what
// parses, written out and parsed again, must write the same text (else a finding naming `what`).
template <class T>
bool round_trip(const std::uint8_t* data, std::size_t size, T& out, const std::string& what) {
  namespace fuzz = skin::fuzz;
  if (!fuzz::accepts([&] { out = T::parse(fuzz::text(data, size), "fuzz.csv"); })) return false;
  const std::string csv = out.to_csv();
  T again;
  if (!fuzz::accepts([&] { again = T::parse(csv, "re-written"); })) fuzz::finding("the re-written " + what + ": not parsed again");
  if (again.to_csv() != csv) fuzz::finding("the re-written " + what + ": read differently");
  return true;
}
// The same input read as the table's offsets (data/skin_stack_offsets.csv): what parses writes
// out and reads back the same; with the built-in table, when its x nodes pair with the table's,
// the profile of skin of another g, index and dermis ratio inside its ranges is finite and >= 0.
void offsets(const std::uint8_t* data, std::size_t size) {
  using skin::transport::accurate::SkinStackOffsets;
  using skin::transport::accurate::SkinStackTable;
  namespace fuzz = skin::fuzz;
  SkinStackOffsets o;
  if (!round_trip(data, size, o, "offsets")) return;
  static SkinStackTable table = SkinStackTable::builtin();  // (libFuzzer runs one input at a time)
  if (o.x.size() < 4 || (table.x.size() - 1) % (o.x.size() - 1) != 0) return;
  const std::size_t stride = (table.x.size() - 1) / (o.x.size() - 1);
  for (std::size_t i = 0; i < o.x.size(); ++i)
    if (std::abs(o.x[i] / table.x[stride * i] - 1) > 1e-6) return;
  table.offsets = &o;
  const double s = 5.0, tau = 1.0, a_e = 0.1, a_d = 0.05;
  auto mid = [](const std::vector<double>& v) { return 0.5 * (v.front() + v.back()); };
  const double g = mid(o.nodes[0]), eta = mid(o.nodes[1]), ratio = mid(o.nodes[2]);
  if (!(std::abs(g) < 1 && eta >= 1 && eta <= 3 && ratio > 0)) return;
  skin::physics::LayerStack stack;
  stack.layers = {skin::physics::Layer{a_e * s, s, tau / s, eta, g},
                  skin::physics::Layer{a_d * s, ratio * s, skin::physics::kInfinity, eta, g}};
  if (!table.gap(stack).empty()) return;
  check_profile(skin::transport::accurate::SkinStackProfile(table, stack, 0.5),
                "the profile of a covered stack with offsets is not finite and >= 0");
}
// The same input read as the offsets' cross terms (data/skin_stack_cross.csv): what parses
// writes out and reads back the same, and the terms added in the middle of the ranges are finite.
void cross(const std::uint8_t* data, std::size_t size) {
  using skin::transport::accurate::SkinStackCross;
  namespace fuzz = skin::fuzz;
  SkinStackCross c;
  if (!round_trip(data, size, c, "cross terms")) return;
  std::vector<double> dt(c.x.size(), 0.0), dl(c.x.size(), 0.0);
  auto mid = [](const std::vector<double>& v) { return std::sqrt(v.front() * v.back()); };
  std::array<double, 3> v{};
  for (std::size_t a = 0; a < 3; ++a) v[a] = 0.5 * (c.ends[a][0] + c.ends[a][1]);
  c.add(mid(c.tau), mid(c.a_e), mid(c.a_d), v, dt, dl);
  for (std::size_t i = 0; i < dt.size(); ++i)
    if (!std::isfinite(dt[i]) || !std::isfinite(dl[i])) fuzz::finding("the cross terms added are not finite");
}
// The same input read as the half-space table: what parses writes out and reads back the same,
// and the profile of a half-space in the middle of its ranges is finite and >= 0.
void half_spaces(const std::uint8_t* data, std::size_t size) {
  using skin::transport::accurate::HalfSpaceTable;
  namespace fuzz = skin::fuzz;
  HalfSpaceTable t;
  if (!round_trip(data, size, t, "half-space table")) return;
  auto mid = [](const std::vector<double>& v) { return 0.5 * (v.front() + v.back()); };
  const double a = std::sqrt(t.a.front() * t.a.back()), g = mid(t.g), eta = mid(t.eta), s = 5.0;
  if (!t.gap(a, g, eta).empty()) return;
  check_profile(skin::transport::accurate::SkinStackProfile(t.x, t.ln_rho_at(a, g, eta), s, 0.5),
                "the profile of a covered half-space is not finite and >= 0");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using skin::transport::accurate::SkinStackTable;
  namespace fuzz = skin::fuzz;
  offsets(data, size);
  cross(data, size);
  half_spaces(data, size);
  SkinStackTable table;
  if (!round_trip(data, size, table, "table")) return 0;
  // A stack in the middle of the table's ranges (s = 5 /mm), with its own geometry.
  const double s = 5.0, tau = std::sqrt(table.tau.front() * table.tau.back());
  const double a_e = std::sqrt(table.a_e.front() * table.a_e.back());
  const double a_d = std::sqrt(table.a_d.front() * table.a_d.back());
  skin::physics::LayerStack stack;
  stack.layers = {skin::physics::Layer{a_e * s, s, tau / s, table.eta, table.g},
                  skin::physics::Layer{a_d * s, table.dermis_ratio * s, skin::physics::kInfinity, table.eta, table.g}};
  if (!(table.eta >= 1 && table.eta <= 3 && std::abs(table.g) < 1 && table.dermis_ratio > 0)) return 0;
  auto check = [](const skin::transport::accurate::SkinStackProfile& profile) {
    check_profile(profile, "the profile of a covered stack is not finite and >= 0");
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
