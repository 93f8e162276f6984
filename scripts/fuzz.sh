#!/usr/bin/env bash
# Runs every fuzz target of a build for a bounded time (docs/testing.md, "Fuzz targets").
#   scripts/fuzz.sh BUILD_DIR SECONDS_PER_TARGET [TARGET...]
# With libFuzzer (a clang sanitize build): each target searches for SECONDS, starting from the
# seed corpus fuzz/corpus/<name>/ and what earlier runs found (BUILD_DIR/fuzz-corpus/<name>/, kept
# between runs, never written into the repository). Without libFuzzer (g++): each target replays
# its corpus once. Exits non-zero on the first crash, hang (an input taking over 30 s), sanitizer
# report, leak, out-of-memory or failed output check; the input is kept in BUILD_DIR/fuzz-findings/
# and the command that reproduces it is printed.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: scripts/fuzz.sh BUILD_DIR SECONDS_PER_TARGET [TARGET...]}
seconds=${2:?usage: scripts/fuzz.sh BUILD_DIR SECONDS_PER_TARGET [TARGET...]}
shift 2
if [[ $# -gt 0 ]]; then targets=("$@"); else mapfile -t targets < "$build/fuzz_targets.txt"; fi

libfuzzer=0
if grep -q '^ANISO_LIBFUZZER:INTERNAL=1' "$build/CMakeCache.txt" 2>/dev/null; then libfuzzer=1; fi
if [[ $libfuzzer == 0 ]]; then
  echo "fuzz: libFuzzer not available in $build (it needs clang and libclang-rt-14-dev): replaying the corpus only"
fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
findings="$build/fuzz-findings"
mkdir -p "$findings"
start=$SECONDS
for t in "${targets[@]}"; do
  [[ -z "$t" ]] && continue
  bin="$build/bin/fuzz_$t"
  seeds="fuzz/corpus/$t"
  [[ -x "$bin" ]] || { echo "fuzz: $bin is missing (build the fuzz_targets target)"; exit 1; }
  [[ -d "$seeds" ]] || { echo "fuzz: $seeds is missing (every target needs a seed corpus)"; exit 1; }
  if [[ $libfuzzer == 1 ]]; then
    found="$build/fuzz-corpus/$t"
    mkdir -p "$found"
    echo "fuzz: $t for ${seconds} s"
    # -timeout: an input that runs over 30 s is a hang. -rss_limit_mb / -malloc_limit_mb: a reader
    # that allocates over 2 GiB for one input is a finding (image headers must be checked against
    # the data size before allocating). -max_len: inputs up to 64 KiB (the seeds are below 4 KiB).
    if ! "$bin" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536 \
        -print_final_stats=1 -artifact_prefix="$findings/$t-" "$found" "$seeds" > "$findings/$t.log" 2>&1; then
      tail -n 60 "$findings/$t.log"
      echo "fuzz: $t FAILED; the input is in $findings/ (reproduce: $bin $findings/$t-<file>)"
      exit 1
    fi
    grep -E '^stat::number_of_executed_units|^stat::new_units_added' "$findings/$t.log" | tr '\n' ' ' | sed "s/^/fuzz: $t: /"
    echo
  else
    if ! "$bin" "$seeds" > "$findings/$t.log" 2>&1; then
      tail -n 60 "$findings/$t.log"
      echo "fuzz: $t FAILED on its corpus"
      exit 1
    fi
    echo "fuzz: $t: $(tail -n 1 "$findings/$t.log")"
  fi
done
echo "fuzz: ${#targets[@]} targets, no findings ($((SECONDS - start)) s)"
