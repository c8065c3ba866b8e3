// The inputs of `skin batch`: the --sets CSV (skin::util::parse_csv, then skin::batch::sets_from_table
// and validation of its sets), and every line of the input also as a --sweep and a --rows value
// (skin::batch::parse_sweep, parse_rows).
// Invariants: a table's sets take the table's values (NaN keeps the base); a sweep's values run
// from START to STOP exactly (COUNT = 1: START alone), inside the parameter's range; rows are a slice of the sets.
#include <cmath>

#include "fuzz_support.hpp"
#include "skin/batch/sets.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/util/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  using skin::util::Table;
  using skin::util::parse_csv;
  using skin::physics::SkinParameters;
  using skin::physics::find_preset;
  const std::string_view input = fuzz::text(data, size);
  const SkinParameters base = find_preset("caucasian").parameters;
  Table table;
  batch::Sets sets;
  if (fuzz::accepts([&] { table = parse_csv(input, "sets.csv"); }) &&
      fuzz::accepts([&] { sets = batch::sets_from_table(table, base); })) {
    if (sets.count != table.rows() || sets.keys.size() != table.columns.size())
      fuzz::finding("the sets are not the table's rows and columns");
    const std::size_t n = std::min<std::size_t>(sets.count, 64);
    fuzz::accepts([&] { sets.validate(0, n); });
    for (std::size_t i = 0; i < n; ++i) {
      const SkinParameters p = sets.at(i);
      for (std::size_t k = 0; k < sets.keys.size(); ++k) {
        const double want = std::isnan(table.data[k][i]) ? base.*(sets.keys[k]->member) : table.data[k][i];
        const double got = p.*(sets.keys[k]->member);
        if (!(got == want) && !(std::isnan(got) && std::isnan(want)))
          fuzz::finding("a set does not hold its table's value");
      }
    }
  }
  // Each line as a sweep and as a row range.
  std::size_t start = 0;
  while (start <= input.size()) {
    std::size_t end = input.find('\n', start);
    if (end == std::string_view::npos) end = input.size();
    const std::string_view line = input.substr(start, end - start);
    batch::Sweep s;
    if (fuzz::accepts([&] { s = batch::parse_sweep(line); })) {
      if (s.count < 1 || s[0] != s.start || (s.count > 1 && s[s.count - 1] != s.stop))
        fuzz::finding("a sweep does not run from START to STOP");
      for (const double v : {s.start, s.stop, s[s.count / 2]})
        if (!fuzz::accepts([&] { s.info->check(v); }))
          fuzz::finding("a sweep's value lies outside its parameter's range");
    }
    std::pair<std::size_t, std::size_t> rows;
    if (fuzz::accepts([&] { rows = batch::parse_rows(line, 1000); }))
      if (rows.first > rows.second || rows.second > 1000) fuzz::finding("rows are not a slice of the sets");
    start = end + 1;
  }
  return 0;
}
