#pragma once
// Numeric CSV tables: the project's data files and users' measured spectra.
// Lines starting with '#' are comments; the first other line holds the column names (a first
// line of numbers only is refused: a file without its header line); every following non-empty
// line holds numbers (an empty field reads as NaN, the mark of a missing value; the text "nan"
// is refused). A UTF-8 byte-order mark at the start is skipped.
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace skin::util {

struct Table {
  std::string source;                     // file name, for messages
  std::vector<std::string> columns;       // header names
  std::vector<std::vector<double>> data;  // data[column][row]

  std::size_t rows() const { return data.empty() ? 0 : data.front().size(); }
  // Index of a column by name; throws InputError naming the source if absent.
  std::size_t column(std::string_view name) const;
};

// Parses CSV text. Throws InputError("<source>:<line>: ...") on a malformed line (wrong number of
// fields, a field that is not a number) or when there is no header or no data row.
Table parse_csv(std::string_view text, const std::string& source);
// Reads and parses a file; throws InputError naming the file when it cannot be read.
Table read_csv_file(const std::string& path);

// Metadata of a data file: its comment lines of the form "# key: value" (the first of a repeated
// key wins), e.g. "# provenance: ..." or "# rho_edges: 0,0.001,...".
std::map<std::string, std::string, std::less<>> csv_metadata(std::string_view text);
// The numbers of a metadata line "# key: 1,2,3" (parse_number_list), and the one number of
// "# key: 1"; InputError "<source>: missing the '# key:' line", "'key' must be one number".
std::vector<double> metadata_numbers(const std::map<std::string, std::string, std::less<>>& meta,
                                     std::string_view key, std::string_view source);
double metadata_number(const std::map<std::string, std::string, std::less<>>& meta,
                       std::string_view key, std::string_view source);
// A comma-separated list of numbers ("0,0.001,2.5"); InputError naming `source` and `key` for a
// field that is not a number.
std::vector<double> parse_number_list(std::string_view list, std::string_view source,
                                      std::string_view key);
// The inverse: "%.7g" values joined by commas.
std::string format_number_list(const std::vector<double>& v);

namespace data {
// Text of a data file compiled into the library (data/*.csv), by file name; throws if unknown.
std::string_view embedded(std::string_view name);
// The embedded file parsed as a Table.
const Table& embedded_table(std::string_view name);
}  // namespace data

}  // namespace skin::util
