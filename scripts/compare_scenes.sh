#!/usr/bin/env bash
# Error against run time on the shipped scenes (doc/coarsening.md): runs
# 'Run type = compare' on each scene given (default: all of them) with the
# Release build, one after the other, and writes
# output/compare/<scene>/comparison.{csv,json}, error_vs_time.png and VTU.
# The metamaterials a scene needs are fitted into the database file on its
# first run (lazy mode); later runs find them there. At the end it prints the
# table of doc/coarsening.md and the targets each scene state meets
# (scripts/compare_table.py), also into output/compare/table.md. Not part of
# the tests: the whole set takes about an hour on a 2-core machine.
#
#   scripts/compare_scenes.sh                  # every scene
#   scripts/compare_scenes.sh bending twisting # some of them
#   EXTRA='--set "Comparison/Fine direct solver limit=40000"' scripts/compare_scenes.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(pushing bending twisting buckling fibers \
                                   bridge bridge_arch shoe_sole character)
for s in "${scenes[@]}"; do
  echo "=== $s"
  eval build/ddfem "prm/$s.prm" --set "'Run type=compare'" \
    --set "'Output/Output directory=output/compare/$s'" \
    --set "'Output/Write VTU=last step'" "${EXTRA:-}"
done
python3 scripts/compare_table.py output/compare "${scenes[@]}" |
  tee output/compare/table.md
