// The Python module's conversions that need no Python (python/convert.hpp): the layer dicts of
// layers() and mc(layers=...), and the linear sRGB values of fit_texture(). The bytes are read as
// text lines: "rgb W v v v ..." gives texture values (W pixels a row); any other line is one
// layer dict, "key=value" items separated by commas, the value "None" or a number as strtod reads
// it (nan, inf, hex floats). Invariants: an accepted layer has both coefficients and every value
// given (no default replaces one); accepted texture values are all in [0, 1].
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "convert.hpp"
#include "fuzz_support.hpp"

namespace {

using Entries = std::vector<std::pair<std::string, std::optional<double>>>;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (char c : s) {
    if (c == sep) out.emplace_back();
    else out.back() += c;
  }
  return out;
}

Entries entries_of(const std::string& line) {
  Entries e;
  if (line.empty()) return e;
  for (const std::string& item : split(line, ',')) {
    const std::size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (value == "None") e.emplace_back(key, std::nullopt);
    else e.emplace_back(key, std::strtod(value.c_str(), nullptr));
  }
  return e;
}

bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  using skin::physics::Layer;
  using skin::physics::LayerStack;
  const std::vector<std::string> lines = split(std::string(fuzz::text(data, size)), '\n');
  LayerStack stack;
  for (const std::string& line : lines) {
    if (line.rfind("rgb ", 0) == 0) {
      const std::vector<std::string> words = split(line.substr(4), ' ');
      const auto width = static_cast<std::size_t>(std::strtoul(words[0].c_str(), nullptr, 10) % 4096);
      std::vector<float> rgb;
      for (std::size_t i = 1; i < words.size(); ++i) rgb.push_back(std::strtof(words[i].c_str(), nullptr));
      bool in_range = true;
      for (float v : rgb) in_range = in_range && v >= 0.0f && v <= 1.0f;
      if (fuzz::accepts([&] { python::check_linear_rgb(rgb, width); }) != in_range)
        fuzz::finding("check_linear_rgb: " + std::string(in_range ? "refused" : "accepted") + " '" + line + "'");
      continue;
    }
    const Entries e = entries_of(line);
    Layer l;
    if (!fuzz::accepts([&] { l = python::layer_from_entries(e, stack.layers.size()); })) continue;
    // The last number given for each key (thickness_mm and thickness are one key).
    std::optional<double> given[5];  // sigma_a, sigma_s_prime, thickness, eta, g
    for (const auto& [key, v] : e) {
      const int k = key == "sigma_a" ? 0 : key == "sigma_s_prime" ? 1 : key == "eta" ? 3 : key == "g" ? 4 : 2;
      if (v) given[k] = v;
    }
    if (!given[0] || !given[1]) fuzz::finding("a layer without sigma_a or sigma_s_prime was accepted: '" + line + "'");
    const double used[5] = {l.sigma_a, l.sigma_s_prime, l.thickness, l.eta, l.g};
    for (int k = 0; k < 5; ++k)
      if (given[k] && !same(*given[k], used[k])) fuzz::finding("a value given was not used: '" + line + "'");
    stack.layers.push_back(l);
  }
  if (!stack.layers.empty()) (void)fuzz::accepts([&] { stack.validate(); });
  return 0;
}
