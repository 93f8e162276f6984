#!/bin/sh
# examples/cpp/check_quickstart.sh QUICKSTART CLI: the README's example prints what
# `aniso eval --angles -m brushed-gold` prints for "30 0 30 180" (f_r f_g f_b pdf), within 1e-6
# relative (the example writes its directions as decimals, the CLI from the angles).
set -u
ours=$("$1") || exit 1
cli=$(echo "30 0 30 180" | "$2" eval --angles -m brushed-gold) || exit 1
echo "quickstart: $ours"
echo "aniso eval: $cli"
echo "$ours $cli" | awk '{ for (i = 1; i <= 4; i++) { d = $i - $(i + 4); if (d < 0) d = -d; m = $(i + 4); if (m < 0) m = -m;
                               if (NF != 8 || d > 1e-6 * m + 1e-12) exit 1 } }'
