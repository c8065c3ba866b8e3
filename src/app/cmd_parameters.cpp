// skin parameters: the parameter table (key, paper symbol, unit, range, default, help), the one
// list every other surface (flags, JSON, scenes, EXR channels, Python, the fit) is made from.
#include "common.hpp"

namespace skin::cli {
namespace {

void register_parameters(CLI::App& app) {
  auto out = std::make_shared<OutputOptions>();
  CLI::App* sub = app.add_subcommand(
      "parameters",
      "List the model parameters: key (JSON, scene, EXR channel, Python keyword; the CLI flag is "
      "the key with dashes), the paper's symbol (accepted as an alias), unit, allowed range, "
      "default and help");
  out->add_to(*sub);
  sub->callback([out] { out->write(schema::parameters_result()); });
}

}  // namespace

SKIN_REGISTER_COMMAND(55, register_parameters);

}  // namespace skin::cli
