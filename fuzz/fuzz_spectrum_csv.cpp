// Measured spectra (skin fit --spectrum FILE.csv [--column NAME], the measured-spectra report):
// the CSV reader (skin::util::parse_csv) and the spectrum readers of the fit (skin::fit::read_spectrum
// with and without a column, read_spectra) on the same file.
#include "fuzz_support.hpp"
#include "skin/fit/fit.hpp"
#include "skin/util/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  using skin::util::Table;
  using skin::util::parse_csv;
  static fuzz::InputFile input("csv");
  const std::string& path = input.write(data, size);
  Table table;
  if (!fuzz::accepts([&] { table = parse_csv(fuzz::text(data, size), path); })) return 0;
  if (table.columns.empty() || table.data.size() != table.columns.size())
    fuzz::finding("a parsed table has no columns or a column without data");
  for (const auto& column : table.data)
    if (column.size() != table.rows()) fuzz::finding("a parsed table has columns of different lengths");
  fuzz::accepts([&] { fit::read_spectrum(path); });
  fuzz::accepts([&] { fit::read_spectra(path); });
  if (table.columns.size() > 1) fuzz::accepts([&] { fit::read_spectrum(path, table.columns.back()); });
  return 0;
}
