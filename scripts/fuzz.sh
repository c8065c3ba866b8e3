#!/usr/bin/env bash
# Builds the libFuzzer harnesses of fuzz/ (clang, -fsanitize=fuzzer,address,undefined, in
# build-fuzz/: scripts/configure-asan.sh --fuzz) and runs each for SECONDS (default 60), starting from
# its seed corpus fuzz/corpus/<target>/ (never modified: new inputs go to
# build-fuzz/fuzz-corpus/<target>/).
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]
#   SKIN_FUZZ_DIR=build-asan bash scripts/fuzz.sh 3   the harnesses of the sanitizer build
#       instead (coverage of the harnesses' own code only; CI's short run, scripts/test.sh)
# A crash, hang (> 10 s on one input), out-of-memory (> 2 GB) or sanitizer report stops that
# target and leaves its input in build-fuzz/fuzz-findings/; the script then exits 1. At the end it
# prints one line per target: executions, and the corpus size.
#   SKIN_FUZZ_MERGE=1 bash scripts/fuzz.sh ...   then minimises each target's seeds together with
#       what the run found (libFuzzer -merge=1) into fuzz/corpus/<target>/, the corpus kept in the
#       repository (so that later runs, CI's included, start from the coverage already found).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
dir=${SKIN_FUZZ_DIR:-build-fuzz}
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR=1  # (scripts/test.sh)
if [ "$dir" = build-fuzz ]; then
  [ -f "$dir/CMakeCache.txt" ] || bash scripts/configure-asan.sh --fuzz
elif [ ! -f "$dir/CMakeCache.txt" ]; then
  echo "fuzz.sh: SKIN_FUZZ_DIR=$dir is not a configured build (scripts/configure-asan.sh)" >&2
  exit 2
fi
cmake --build "$dir" --target fuzz_all
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for f in "$dir"/bin/fuzz_*; do targets+=("$(basename "$f")"); done
fi
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mkdir -p "$dir/fuzz-findings" "$dir/fuzz-logs"
failed=0
summary=()
for t in "${targets[@]}"; do
  mkdir -p "$dir/fuzz-corpus/$t"
  seeds=fuzz/corpus/$t
  log=$dir/fuzz-logs/$t.log
  status=ok
  if ! "$dir/bin/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$dir/fuzz-findings/$t-" "$dir/fuzz-corpus/$t" "$seeds" >"$log" 2>&1; then
    status="FINDING (see $log and $dir/fuzz-findings/)"
    failed=1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  summary+=("$(printf '%-22s %10s executions in %ss, corpus %s files  %s' "$t" "$execs" "$seconds" \
    "$(ls "$dir/fuzz-corpus/$t" | wc -l)" "$status")")
done
printf '%s\n' "${summary[@]}"
if [ "${SKIN_FUZZ_MERGE:-0}" = 1 ] && [ $failed = 0 ]; then
  for t in "${targets[@]}"; do
    merged=$(mktemp -d)
    "$dir/bin/$t" -merge=1 -timeout=10 -rss_limit_mb=2048 "$merged" "fuzz/corpus/$t" "$dir/fuzz-corpus/$t" \
      >"$dir/fuzz-logs/$t.merge.log" 2>&1
    rm -rf "fuzz/corpus/$t"
    mv "$merged" "fuzz/corpus/$t"
    chmod 755 "fuzz/corpus/$t"
    echo "$t: fuzz/corpus/$t minimised to $(ls "fuzz/corpus/$t" | wc -l) files"
  done
fi
exit $failed
