#!/usr/bin/env bash
# Runs every fuzz target of a build (docs/testing.md, "Fuzz targets").
#   scripts/fuzz.sh BUILD_DIR SECONDS_PER_TARGET [TARGET...]   search for SECONDS each, random seeds
#   scripts/fuzz.sh --ci BUILD_DIR [TARGET...]                  CI's run: fixed seeds and lengths
# With libFuzzer (a clang sanitize build): each target searches from the seed corpus
# fuzz/corpus/<name>/. A developer's run (SECONDS) starts from a random seed and from what earlier
# runs found (BUILD_DIR/fuzz-corpus/<name>/, kept between runs, never written into the
# repository). CI's run (--ci) is reproducible: each target runs the number of inputs and from the
# libFuzzer seed that fuzz/ci.txt gives it, from the seed corpus alone (BUILD_DIR/fuzz-ci-corpus/
# is emptied first), so the same sources give the same inputs on every machine, and a finding
# reproduces with the same command. Without libFuzzer (g++): each target replays its corpus once.
# The targets run FUZZ_JOBS at a time (default: the number of cores; each target is one process on
# one core, so on CI's 2 cores two at a time halve the run's wall time), each into its own log;
# each target's lines are printed in the order of the list once all have ended.
# Exits non-zero on any crash, hang (an input taking over 30 s), sanitizer report, leak,
# out-of-memory or failed output check; the input is kept in BUILD_DIR/fuzz-findings/ and the
# command that reproduces it is printed.
set -euo pipefail
cd "$(dirname "$0")/.."
usage="usage: scripts/fuzz.sh BUILD_DIR SECONDS_PER_TARGET [TARGET...] | scripts/fuzz.sh --ci BUILD_DIR [TARGET...]"
ci=0
if [[ "${1:-}" == "--ci" ]]; then
  ci=1
  shift
fi
build=${1:?$usage}
shift
if [[ $ci == 0 ]]; then
  seconds=${1:?$usage}
  shift
fi
if [[ $# -gt 0 ]]; then targets=("$@"); else mapfile -t targets < "$build/fuzz_targets.txt"; fi

# CI's table: "<target> <seed> <runs>" a line (fuzz/ci.txt).
declare -A ci_seed ci_runs
if [[ $ci == 1 ]]; then
  while read -r name seed runs; do
    [[ -z "$name" || "$name" == \#* ]] && continue
    ci_seed[$name]=$seed
    ci_runs[$name]=$runs
  done < fuzz/ci.txt
fi
# A ceiling on one target's time in CI's run (seconds): ci.txt sizes each to about 7 s on the
# 2-core CI machine; a machine this much slower stops early (said in the log, not a failure).
ci_time_cap=60
# One seed does not make two runs identical: libFuzzer re-reads its corpus folder every second
# (-reload, off in CI's run), and the paths through the readers vary a little between processes
# (two runs of fuzz_eval_line, 80000 inputs from one seed, added 962 and 1029 units). What the
# fixed seeds and counts give is the same search, of the same length, on every run: no run explores
# where the others never go, and a finding's input is kept to replay.

libfuzzer=0
if grep -q '^ANISO_LIBFUZZER:INTERNAL=1' "$build/CMakeCache.txt" 2>/dev/null; then libfuzzer=1; fi
if [[ $libfuzzer == 0 ]]; then
  echo "fuzz: libFuzzer not available in $build (it needs clang and libclang-rt-14-dev): replaying the corpus only"
fi

# intercept_tls_get_addr=0: clang 14's LeakSanitizer can crash its own tracer on a dynamic TLS block
# (google/sanitizers#1322; docs/testing.md, "Sanitizers"), as the sanitizer preset sets too.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
findings="$build/fuzz-findings"
mkdir -p "$findings"
start=$SECONDS
# fuzz_target NAME: one target's run; its lines on stdout, non-zero on a finding.
fuzz_target() {
  local t=$1 bin seeds found executed
  local -a run_flags
  bin="$build/bin/fuzz_$t"
  seeds="fuzz/corpus/$t"
  [[ -x "$bin" ]] || { echo "fuzz: $bin is missing (build the fuzz_targets target)"; return 1; }
  [[ -d "$seeds" ]] || { echo "fuzz: $seeds is missing (every target needs a seed corpus)"; return 1; }
  if [[ $libfuzzer == 1 ]]; then
    if [[ $ci == 1 ]]; then
      [[ -n "${ci_seed[$t]:-}" ]] || { echo "fuzz: $t has no line in fuzz/ci.txt (target, seed, runs)"; return 1; }
      found="$build/fuzz-ci-corpus/$t"
      rm -rf "$found"
      run_flags=(-seed="${ci_seed[$t]}" -runs="${ci_runs[$t]}" -reload=0 -max_total_time="$ci_time_cap")
      echo "fuzz: $t, ${ci_runs[$t]} inputs from seed ${ci_seed[$t]}"
    else
      found="$build/fuzz-corpus/$t"
      run_flags=(-max_total_time="$seconds")
      echo "fuzz: $t for ${seconds} s"
    fi
    mkdir -p "$found"
    # -timeout: an input that runs over 30 s is a hang. -rss_limit_mb / -malloc_limit_mb: a reader
    # that allocates over 2 GiB for one input is a finding (image headers must be checked against
    # the data size before allocating). -max_len: inputs up to 64 KiB (the seeds are below 4 KiB).
    if ! "$bin" "${run_flags[@]}" -timeout=30 -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536 \
        -print_final_stats=1 -artifact_prefix="$findings/$t-" "$found" "$seeds" > "$findings/$t.log" 2>&1; then
      tail -n 60 "$findings/$t.log"
      echo "fuzz: $t FAILED; the input is in $findings/ (reproduce: $bin $findings/$t-<file>)"
      if [[ $ci == 1 ]]; then
        echo "fuzz: the same run again: scripts/fuzz.sh --ci $build $t"
      fi
      return 1
    fi
    grep -E '^stat::number_of_executed_units|^stat::new_units_added' "$findings/$t.log" | tr '\n' ' ' | sed "s/^/fuzz: $t: /"
    echo
    executed=$(sed -n 's/^stat::number_of_executed_units: *//p' "$findings/$t.log")
    if [[ $ci == 1 && "${executed:-0}" -lt "${ci_runs[$t]}" ]]; then
      echo "fuzz: $t stopped at the ${ci_time_cap} s ceiling after ${executed:-0} of its ${ci_runs[$t]} inputs (a slow machine)"
    fi
  else
    if ! "$bin" "$seeds" > "$findings/$t.log" 2>&1; then
      tail -n 60 "$findings/$t.log"
      echo "fuzz: $t FAILED on its corpus"
      return 1
    fi
    echo "fuzz: $t: $(tail -n 1 "$findings/$t.log")"
  fi
}

jobs=${FUZZ_JOBS:-$(nproc)}
running=0
for t in "${targets[@]}"; do
  [[ -z "$t" ]] && continue
  rm -f "$findings/$t.status"
  (if fuzz_target "$t" > "$findings/$t.out" 2>&1; then echo 0; else echo 1; fi > "$findings/$t.status") &
  running=$((running + 1))
  if ((running >= jobs)); then
    wait -n || true
    running=$((running - 1))
  fi
done
wait
failed=0
for t in "${targets[@]}"; do
  [[ -z "$t" ]] && continue
  cat "$findings/$t.out"
  [[ "$(cat "$findings/$t.status" 2>/dev/null)" == 0 ]] || failed=1
done
((failed == 0)) || exit 1
echo "fuzz: ${#targets[@]} targets, no findings ($((SECONDS - start)) s)"
