// Parameter files (--params FILE.json): read as the CLI reads them (skin::cli::ParameterFile),
// applied to the defaults and validated. Invariant: the values read, written back as a bare
// object of parameter keys and read again, are the same values.
#include <cstdio>
#include <fstream>

#include "common.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  using skin::physics::ParameterInfo;
  using skin::physics::SkinParameters;
  using skin::physics::parameter_table;
  static fuzz::InputFile input("json");
  const std::string& path = input.write(data, size);
  cli::ParameterFile file;
  if (!fuzz::accepts([&] {
        file = cli::ParameterFile::read(path);
        SkinParameters p;
        file.apply(p);
        p.validate();
      }))
    return 0;
  cli::json doc = cli::json::object();
  if (!file.preset.empty()) doc["preset"] = file.preset;
  for (const auto& [info, v] : file.values) doc[std::string(info->key)] = v;
  std::ofstream(path, std::ios::trunc) << doc.dump();
  cli::ParameterFile again;
  if (!fuzz::accepts([&] { again = cli::ParameterFile::read(path); }))
    fuzz::finding("the re-written parameters do not read: " + doc.dump());
  SkinParameters a, b;
  file.apply(a);
  again.apply(b);
  for (const ParameterInfo& info : parameter_table())
    if (!(a.*(info.member) == b.*(info.member)))
      fuzz::finding("re-read parameter differs: " + std::string(info.key));
  return 0;
}
