#!/bin/sh
# examples/cpp/compare_with_cli.sh: runs an example that prints materials and their values, and
# compares every value with what the `aniso` CLI prints for the same material and directions.
#
#   compare_with_cli.sh CLI TOLERANCE PROGRAM [ARGS...]
#
# PROGRAM prints blocks of the form
#   # material <spec>                          a preset name, a JSON file or inline JSON
#   theta_i phi_i theta_o phi_o f_r f_g f_b pdf    (degrees; any number of lines)
# For each block this runs `CLI eval --angles --material <spec>` on the four angle columns and
# checks each of the four values against the CLI's within TOLERANCE relative (two zeros agree).
# Prints the largest relative difference found; exit status 1 on a mismatch or a failed command.
# CLI may be empty: then the program runs (a failure still fails) and the script exits 77, which
# the tests declare as "skipped" (SKIP_RETURN_CODE), with a message saying why.
set -u
cli=$1
tolerance=$2
shift 2

work=$(mktemp -d "${TMPDIR:-/tmp}/aniso-compare.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT

if ! "$@" >"$work/program.txt"; then
  cat "$work/program.txt"
  echo "compare_with_cli: $1 failed" >&2
  exit 1
fi
cat "$work/program.txt"
if [ -z "$cli" ]; then
  echo "compare_with_cli: ANISO_CLI is not set: the comparison with \`aniso eval\` is skipped"
  exit 77
fi

# Split the output into one spec, angle and value file per block.
awk -v dir="$work" '
  /^# material / { n++; print substr($0, 12) > (dir "/spec" n); next }
  /^#/ || NF == 0 { next }
  NF == 8 && n > 0 {
    print $1, $2, $3, $4 > (dir "/angles" n)
    print $5, $6, $7, $8 > (dir "/values" n)
  }
  END { print n + 0 > (dir "/count") }' "$work/program.txt"

blocks=$(cat "$work/count")
if [ "$blocks" -eq 0 ]; then
  echo "compare_with_cli: the program printed no \"# material\" block" >&2
  exit 1
fi
status=0
i=1
while [ "$i" -le "$blocks" ]; do
  spec=$(cat "$work/spec$i")
  if ! "$cli" eval --angles --material "$spec" <"$work/angles$i" >"$work/cli$i"; then
    echo "compare_with_cli: $cli eval --angles --material '$spec' failed" >&2
    exit 1
  fi
  # Both files have one line per pair; the CLI's numbers follow the program's on each line.
  if ! paste -d ' ' "$work/values$i" "$work/cli$i" | awk -v tol="$tolerance" -v spec="$spec" '
    function abs(x) { return x < 0 ? -x : x }
    {
      if (NF != 8) { printf "line %d: %d numbers, expected 4 from each side\n", NR, NF; bad = 1; next }
      for (k = 1; k <= 4; k++) {
        a = $k + 0; b = $(k + 4) + 0
        scale = abs(a) > abs(b) ? abs(a) : abs(b)
        rel = scale > 0 ? abs(a - b) / scale : 0
        if (rel > worst) worst = rel
        if (rel > tol) { printf "MISMATCH %s line %d value %d: program %s, aniso eval %s\n", spec, NR, k, $k, $(k + 4); bad = 1 }
      }
      lines++
    }
    END {
      printf "compared %d pairs of %s with aniso eval: largest relative difference %.3g\n", lines, spec, worst
      exit bad
    }'; then
    status=1
  fi
  i=$((i + 1))
done
exit $status
