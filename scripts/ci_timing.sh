#!/usr/bin/env bash
# scripts/ci_timing.sh [COMMIT] [DIR]: CI's run (.ci/run) on a clean clone of COMMIT (default HEAD)
# in DIR (default aniso-ci-<commit> beside this checkout, so that the tests find ../shared/data as
# CI's do), timed, for docs/testing.md's "CI time" table.
#
# .ci/run prints each step's wall and CPU time ("ci-step" lines) and each suite's ten slowest
# entries (scripts/ctest_timed.sh); this runs it on a fresh clone (nothing built, no ctest cost
# data, so ctest orders the entries by their COST properties as on CI), keeps the whole log in
# DIR.log, and ends with what the table needs: the steps, the two suites' summaries, the total,
# the date, the commit and the machine. Uncommitted changes are not in the clone: commit first.
# The exit status is .ci/run's.
set -uo pipefail
cd "$(dirname "$0")/.."
commit=$(git rev-parse --short "${1:-HEAD}") || exit 2
dir=${2:-$(dirname "$(pwd)")/aniso-ci-$commit}
log=$dir.log
if [[ -e "$dir" ]]; then
  echo "ci_timing: $dir exists; remove it or name another directory" >&2
  exit 2
fi
git clone -q --no-hardlinks "$(pwd)" "$dir" && git -C "$dir" checkout -q "$commit" || exit 2
echo "ci_timing: .ci/run on a clean clone of $commit in $dir (log: $log)"
start=$(date +%s)
(cd "$dir" && bash .ci/run) >"$log" 2>&1
status=$?
wall=$(($(date +%s) - start))
{
  echo
  echo "=== ci_timing: $commit, $(date -u '+%Y-%m-%d %H:%M UTC'), exit status $status"
  echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), load before the end: $(cut -d' ' -f1-3 /proc/loadavg)"
  grep -E '^(=== ctest --preset|=== [0-9]+ entries|  +[0-9.]+ s  )' "$log"
  grep -E '^(=== \.ci/run:|ci-step: )' "$log" | tail -n 7
  echo "whole run: ${wall} s wall"
} | tee -a "$log"
exit "$status"
