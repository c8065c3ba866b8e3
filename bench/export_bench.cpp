// Cost of an export: one target, and all nine for one parameter set (the bound: < 1 s).
#include <benchmark/benchmark.h>

#include "skin/export/export.hpp"

using namespace skin;
using skin::physics::SkinParameters;
using skin::physics::find_preset;

static void BM_ExportTarget(benchmark::State& state) {
  const exporting::Target& t = exporting::targets()[static_cast<std::size_t>(state.range(0))];
  state.SetLabel(std::string(t.name));
  const SkinParameters p = find_preset("caucasian").parameters;
  for (auto _ : state) {
    exporting::Export e = exporting::export_skin(t.name, p, transport::default_model(), {});
    benchmark::DoNotOptimize(e);
  }
}
BENCHMARK(BM_ExportTarget)->DenseRange(0, 8)->Unit(benchmark::kMillisecond);

static void BM_ExportAllTargets(benchmark::State& state) {
  const SkinParameters p = find_preset("caucasian").parameters;
  for (auto _ : state)
    for (const exporting::Target& t : exporting::targets()) {
      exporting::Export e = exporting::export_skin(t.name, p, transport::default_model(), {});
      benchmark::DoNotOptimize(e);
    }
}
BENCHMARK(BM_ExportAllTargets)->Unit(benchmark::kMillisecond);

// What `skin export --target all` does: our profile once, then every target.
static void BM_ExportAllTargetsPrepared(benchmark::State& state) {
  const SkinParameters p = find_preset("caucasian").parameters;
  for (auto _ : state) {
    const auto ours = exporting::prepare(p, transport::default_model());
    for (const exporting::Target& t : exporting::targets()) {
      exporting::Export e = exporting::export_prepared(t.name, *ours, {});
      benchmark::DoNotOptimize(e);
    }
  }
}
BENCHMARK(BM_ExportAllTargetsPrepared)->Unit(benchmark::kMillisecond);
