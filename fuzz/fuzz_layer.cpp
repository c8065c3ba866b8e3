// The --layer syntax (skin layers, skin mc): one --layer value per line of the input, parsed as
// the CLI parses them (skin::cli::parse_layer, then LayerStack::validate). Invariant: a stack
// that parses, printed in its JSON form (to_json(Layer): the --layer keys) with round-trip
// numbers and parsed again, is the same stack.
#include <cstdio>
#include <string>
#include <vector>

#include "common.hpp"
#include "fuzz_support.hpp"

namespace {

std::string reprint(const skin::physics::Layer& l) {
  std::string spec;
  const skin::cli::json j = skin::cli::to_json(l);  // items() refers to it: kept alive here
  for (const auto& [key, value] : j.items()) {
    if (value.is_null()) continue;  // semi-infinite: no thickness
    char number[40];
    std::snprintf(number, sizeof number, "%.17g", value.get<double>());
    spec += (spec.empty() ? "" : ",") + key + "=" + number;
  }
  return spec;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  using skin::physics::LayerStack;
  using skin::physics::to_string;
  std::vector<std::string> specs;
  std::string line;
  for (char c : fuzz::text(data, size)) {
    if (c == '\n') specs.push_back(std::move(line)), line.clear();
    else line += c;
  }
  if (!line.empty() || specs.empty()) specs.push_back(line);
  LayerStack stack;
  if (!fuzz::accepts([&] {
        for (std::size_t i = 0; i < specs.size(); ++i) stack.layers.push_back(cli::parse_layer(specs[i], i));
        stack.validate();
      }))
    return 0;
  LayerStack again;
  for (std::size_t i = 0; i < stack.layers.size(); ++i) {
    const std::string spec = reprint(stack.layers[i]);
    if (!fuzz::accepts([&] { again.layers.push_back(cli::parse_layer(spec, i)); }))
      fuzz::finding("the re-printed layer '" + spec + "' does not parse");
  }
  if (!(again == stack)) fuzz::finding("re-parsed stack differs: " + to_string(stack) + " vs " + to_string(again));
  return 0;
}
