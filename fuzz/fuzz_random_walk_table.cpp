// The random-walk transport table (data/random_walk_g0.csv, written by
// `skin tabulate-random-walk`, read by the export's random-walk targets):
// skin::transport::RandomWalkTable::from_csv. Invariants: a table that parses, written out
// (to_csv) and parsed again, writes the same text; its reflectance, mean radius and density
// inside its range are finite and non-negative.
#include <cmath>

#include "fuzz_support.hpp"
#include "skin/transport/random_walk_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using skin::transport::RandomWalkTable;
  namespace fuzz = skin::fuzz;
  RandomWalkTable table;
  if (!fuzz::accepts([&] { table = RandomWalkTable::from_csv(fuzz::text(data, size), "fuzz.csv"); })) return 0;
  const std::string csv = table.to_csv();
  RandomWalkTable again;
  if (!fuzz::accepts([&] { again = RandomWalkTable::from_csv(csv, "re-written"); }))
    fuzz::finding("the re-written table does not parse");
  if (again.to_csv() != csv) fuzz::finding("the re-written table reads differently");
  for (const double alpha : {table.alpha.front(), 0.5 * (table.alpha.front() + table.alpha.back()), table.alpha.back()}) {
    const double R = table.reflectance(alpha), m = table.mean_rho(alpha);
    if (!(std::isfinite(R) && R >= 0 && std::isfinite(m) && m >= 0))
      fuzz::finding("the reflectance or mean radius of a parsed table is not finite and >= 0");
    for (const double d : table.density(alpha, {0.01, 1.0, 10.0}))
      if (!(std::isfinite(d) && d >= 0)) fuzz::finding("a density of a parsed table is not finite and >= 0");
  }
  return 0;
}
