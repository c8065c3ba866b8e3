// Transport tables of the top layer (data/top_layer_transport_g*.csv, written by
// skin tabulate-top-layer): skin::accurate::TopLayerTable::parse, then a sample inside the
// table. Invariant: a table that parses, written out (to_csv) and parsed again, writes the same
// text.
#include <cmath>

#include "fuzz_support.hpp"
#include "skin/transport/top_layer_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using skin::accurate::TopLayerTable;
  namespace fuzz = skin::fuzz;
  TopLayerTable table;
  if (!fuzz::accepts([&] { table = TopLayerTable::parse(fuzz::text(data, size), "fuzz.csv"); })) return 0;
  const std::string csv = table.to_csv();
  TopLayerTable again;
  if (!fuzz::accepts([&] { again = TopLayerTable::parse(csv, "re-written"); }))
    fuzz::finding("the re-written table does not parse");
  if (again.to_csv() != csv) fuzz::finding("the re-written table reads differently");
  // Sampling in the middle of its range must give finite numbers.
  const double x = 0.5 * (table.x.front() + table.x.back());
  const double tau = std::sqrt(table.tau.front() * table.tau.back());
  const double alpha_prime = 1 - x * x;
  if (table.covers(alpha_prime, tau)) {
    const auto s = table.sample(alpha_prime, tau);
    if (!std::isfinite(s.R_e) || !std::isfinite(s.T_down) || !std::isfinite(table.R_e_integral(s)))
      fuzz::finding("a sample of a parsed table is not finite");
  }
  return 0;
}
