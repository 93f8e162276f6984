#!/usr/bin/env bash
# scripts/ctest_timed.sh: a ctest run that ends with its times, so that a suite's growth shows in
# every log (docs/testing.md, "CI time").
#
#   scripts/ctest_timed.sh PRESET [CTEST_ARGS...]   ctest --preset PRESET CTEST_ARGS, then the report;
#                                                   exits with ctest's status, whatever the report does
#   scripts/ctest_timed.sh --report BUILD_DIR [N]   the report alone, of BUILD_DIR's last ctest run
#
# The report: the run's wall and CPU time (user + sys of ctest and every test it ran; with --run
# only), the number of entries and the sum of their times, and the N slowest entries (default 10)
# with their times, read from BUILD_DIR/Testing/Temporary/LastTest.log (which holds the last run
# only: after `ctest -R x` it is that run's).
set -uo pipefail
cd "$(dirname "$0")/.."

report() {
  local dir=$1 n=${2:-10}
  local log=$dir/Testing/Temporary/LastTest.log
  if [[ ! -f "$log" ]]; then
    echo "ctest_timed: no $log, no times to report"
    return 0
  fi
  # "N/M Testing: name" opens an entry's block, "Test time =   1.23 sec" closes it.
  awk -v n="$n" -v dir="$dir" '
    / Testing: / && $1 ~ /^[0-9]+\/[0-9]+$/ { name = $3; next }
    /^Test time = / && name != "" { t[name] = $4; sum += $4; count++; name = ""; next }
    END {
      if (count == 0) { print "ctest_timed: no finished entry in " dir "/Testing/Temporary/LastTest.log"; exit }
      printf "=== %d entries, %.0f s of entry time in all (%s); the %d slowest:\n", count, sum, dir, (count < n ? count : n)
      for (k in t) printf "%s %s\n", t[k], k | "sort -g -r | head -n " n " | awk \x27{ printf \"  %8.1f s  %s\\n\", $1, $2 }\x27"
    }' "$log"
}

if [[ "${1:-}" == "--report" ]]; then
  report "${2:?usage: ctest_timed.sh --report BUILD_DIR [N]}" "${3:-10}"
  exit 0
fi

preset=${1:?usage: ctest_timed.sh PRESET [CTEST_ARGS...] | ctest_timed.sh --report BUILD_DIR [N]}
shift
start=$(date +%s)
# The run's own output is what the report reads, and it is kept as
# build/PRESET/Testing/LastRunOutput.txt: LastTest.log is rewritten by any ctest run in the same
# build folder (ctest_every_entry_has_a_timeout runs its ctest on a copy of the test files for that
# reason), and with the presets' outputOnFailure the run's output holds each failed test's output,
# which scripts/ctest_failure_digest.sh reads when LastTest.log lacks it.
out=$(mktemp)
kept=build/$preset/Testing/LastRunOutput.txt
ctest --preset "$preset" "$@" | tee "$out"
status=${PIPESTATUS[0]}
wall=$(($(date +%s) - start))
# bash's `times`: the second line is the user and system time of the finished children (ctest, and
# through it every test), e.g. "1m2.500s 0m3.250s".
times_file=$(mktemp)
times >"$times_file"  # in this shell: in $(...) it would be a subshell's, without ctest
cpu=$(tail -n 1 "$times_file" | awk '
  function s(x,  m) { m = x; sub(/m.*/, "", m); sub(/^[0-9]+m/, "", x); sub(/s$/, "", x); return 60 * m + x }
  { printf "%.0f", s($1) + s($2) }')
rm -f "$times_file"
echo "=== ctest --preset $preset: ${wall} s wall, ${cpu} s CPU (user + sys), exit status $status"
# "  12/1590 Test  #147: Name ......   Passed   22.44 sec": the entry's name and its seconds.
awk '$1 ~ /^[0-9]+\/[0-9]+$/ && $2 == "Test" && $NF == "sec" { name = $4; t = $(NF - 1); if (t + 0 == t) print t, name }' "$out" |
  sort -g -r | head -n 10 | awk 'BEGIN { print "=== the 10 slowest entries of this run:" } { printf "  %8.1f s  %s\n", $1, $2 }'
{ mkdir -p "$(dirname "$kept")" && cp "$out" "$kept"; } || echo "ctest_timed: could not keep the run's output as $kept"
rm -f "$out"
exit "$status"
