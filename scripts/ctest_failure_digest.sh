#!/usr/bin/env bash
# scripts/ctest_failure_digest.sh BUILD_DIR: after a failed ctest run in BUILD_DIR, the reason for
# each failed test in a few short lines (test name, then its sanitizer / assertion / gtest failure
# lines and the last lines of its output), so that the end of a CI log, which is often all that is
# kept, says why and not only which. Called by .ci/run; reads Testing/Temporary/LastTest.log.
set -uo pipefail
dir=${1:?usage: ctest_failure_digest.sh BUILD_DIR}
log=$dir/Testing/Temporary/LastTest.log
failed=$dir/Testing/Temporary/LastTestsFailed.log
[ -f "$log" ] && [ -f "$failed" ] || { echo "ctest_failure_digest: no ctest logs in $dir/Testing/Temporary"; exit 0; }

max_tests=${DIGEST_MAX_TESTS:-4}
echo "=== why the tests failed ($(wc -l <"$failed") failed; the first $max_tests here; whole log: $log)"
head -n "$max_tests" "$failed" | while IFS=: read -r number name; do
  echo "--- test $number: ${name%% *}"
  # The test's output in LastTest.log: after "N/M Testing: name", from the line after "Output:"
  # and its dashed rule to the next "Test time" line.
  awk -v n="$number" '
    $0 ~ "^" n "/[0-9]+ Testing: " { inside = 1; next }
    inside && /^Test time/ { exit }
    inside && /^Output:/ { output = 1; getline; next }
    output { print }' "$log" >"$dir/.digest_block.txt"
  # Sanitizer reports, aborts and assertions first (up to 14 lines), then the output's last 6 lines.
  grep -E 'ERROR: |SUMMARY: |Tracer caught|runtime error|LLVM ERROR|Assertion|terminate called|Failure$|Expected|Which is|Sanitizer|^ *#[0-9]+ 0x' \
    "$dir/.digest_block.txt" | cut -c1-200 | head -n 14
  echo "  [last lines]"
  grep -v -E '^\s*$|^<end of output>' "$dir/.digest_block.txt" | tail -n 6 | cut -c1-200 | sed 's/^/  /'
done
rm -f "$dir/.digest_block.txt"
