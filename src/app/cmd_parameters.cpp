// skin parameters: the parameter table (key, paper symbol, unit, range, default, help), the one
// list every other surface (flags, JSON, scenes, EXR channels, Python, the fit) is made from.
#include <cmath>

#include "common.hpp"
#include "skin/util/error.hpp"

namespace skin::cli {
namespace {

json bound(double v) { return std::isinf(v) ? json(nullptr) : json(v); }

void register_parameters(CLI::App& app) {
  auto out = std::make_shared<OutputOptions>();
  CLI::App* sub = app.add_subcommand(
      "parameters",
      "List the model parameters: key (JSON, scene, EXR channel, Python keyword; the CLI flag is "
      "the key with dashes), the paper's symbol (accepted as an alias), unit, allowed range, "
      "default and help");
  out->add_to(*sub);
  sub->callback([out] {
    const auto table = parameter_table();
    Result result;
    result.document = json::array();
    std::vector<Column> cols = {{"key", {}, {}},      {"flag", {}, {}},    {"symbol", {}, {}},
                                {"unit", {}, {}},     {"min", {}, {}},     {"max", {}, {}},
                                {"min_exclusive", {}, {}}, {"max_exclusive", {}, {}},
                                {"default", {}, {}},  {"help", {}, {}}};
    std::vector<std::vector<std::string>> rows = {
        {"key", "symbol", "unit", "range", "default", "help"}};
    for (const auto& p : table) {
      result.document.push_back({{"key", p.key},
                                 {"flag", "--" + p.flag()},
                                 {"symbol", p.symbol.empty() ? json(nullptr) : json(p.symbol)},
                                 {"unit", p.unit},
                                 {"min", bound(p.min)},
                                 {"max", bound(p.max)},
                                 {"min_exclusive", p.min_open},
                                 {"max_exclusive", p.max_open},
                                 {"default", p.default_value()},
                                 {"help", p.help}});
      const std::string text[] = {std::string(p.key), "--" + p.flag(), std::string(p.symbol),
                                  std::string(p.unit), format_number(p.min), format_number(p.max),
                                  p.min_open ? "true" : "false", p.max_open ? "true" : "false",
                                  format_number(p.default_value()), std::string(p.help)};
      for (std::size_t c = 0; c < cols.size(); ++c) cols[c].text.push_back(text[c]);
      rows.push_back({std::string(p.key), std::string(p.symbol), std::string(p.unit),
                      p.range_text(), format_number(p.default_value()), std::string(p.help)});
    }
    result.columns = cols;
    result.table = format_text_table(rows);
    out->write(result);
  });
}

}  // namespace

SKIN_REGISTER_COMMAND(55, register_parameters);

}  // namespace skin::cli
