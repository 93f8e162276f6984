#!/usr/bin/env bash
# scripts/ctest_failure_digest.sh BUILD_DIR: after a failed ctest run in BUILD_DIR, the reason for
# each failed test in a few short lines (test name, then its sanitizer / assertion / gtest failure
# lines and the last lines of its output), so that the end of a CI log, which is often all that is
# kept, says why and not only which. Called by .ci/run; reads Testing/Temporary/LastTest.log, and
# where that lacks the test's output (any other ctest run in the folder rewrites it) the run's own
# output that scripts/ctest_timed.sh keeps in Testing/LastRunOutput.txt (the presets print a failed
# test's output: outputOnFailure).
set -uo pipefail
dir=${1:?usage: ctest_failure_digest.sh BUILD_DIR}
log=$dir/Testing/Temporary/LastTest.log
run_output=$dir/Testing/LastRunOutput.txt
failed=$dir/Testing/Temporary/LastTestsFailed.log
[ -f "$failed" ] || { echo "ctest_failure_digest: no $failed"; exit 0; }

max_tests=${DIGEST_MAX_TESTS:-4}
block=$dir/.digest_block.txt
echo "=== why the tests failed ($(wc -l <"$failed") failed; the first $max_tests here; whole log: $log)"
head -n "$max_tests" "$failed" | while IFS=: read -r number name; do
  echo "--- test $number: ${name%% *}"
  : >"$block"
  # The test's output in LastTest.log: after "N/M Testing: name", from the line after "Output:"
  # and its dashed rule to the next "Test time" line. (-a: a log rewritten while ctest still
  # appended to it holds NUL bytes.)
  if [ -f "$log" ]; then
    tr -d '\000' <"$log" | awk -v n="$number" '
      $0 ~ "^" n "/[0-9]+ Testing: " { inside = 1; next }
      inside && /^Test time/ { exit }
      inside && /^Output:/ { output = 1; getline; next }
      output { print }' >"$block"
  fi
  # Else the run's output: after the test's result line ("12/1590 Test #507: Name ...***Failed"),
  # up to the next "Start N:" or result line.
  if ! grep -q -v -E '^\s*$|^<end of output>' "$block" && [ -f "$run_output" ]; then
    echo "  (LastTest.log holds no output for it; from the run's output)"
    awk -v n="$number" '
      $0 ~ "Test +#" n ": " { inside = 1; next }
      inside && ($0 ~ /^ *Start +[0-9]+: / || $0 ~ /^ *[0-9]+\/[0-9]+ Test +#/ || $0 ~ /tests passed, /) { exit }
      inside { print }' "$run_output" >"$block"
  fi
  # Sanitizer reports, aborts and assertions first (up to 14 lines), then the output's last 6 lines.
  grep -a -E 'ERROR: |SUMMARY: |Tracer caught|runtime error|LLVM ERROR|Assertion|terminate called|Failure$|Expected|Which is|Sanitizer|^ *#[0-9]+ 0x' \
    "$block" | cut -c1-200 | head -n 14
  echo "  [last lines]"
  grep -a -v -E '^\s*$|^<end of output>' "$block" | tail -n 6 | cut -c1-200 | sed 's/^/  /'
done
rm -f "$block"
