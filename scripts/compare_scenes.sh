#!/usr/bin/env bash
# Error against run time on the shipped scenes (doc/coarsening.md): runs
# 'Run type = compare' on each scene given (a file prm/<scene>.prm; default:
# the nine scenes of the comparison: pushing, bending, twisting, buckling,
# fibers, bridge, bridge_arch, shoe_sole, character) with the Release build,
# one after the other, and writes output/compare/<scene>/comparison.{csv,json},
# error_vs_time.png and VTU. EXTRA holds further arguments of every run (its
# settings of 'Run type' and 'Output/Output directory' are overridden), as
# shell words (quoted as on a command line; split as words only, so '$' and
# backquotes stay as they are). The metamaterials a scene needs
# are fitted into the database file on its first run (lazy mode); later runs
# find them there.
# A compare run in which a model does not converge exits with 1 but writes
# its results; a scene whose run fails goes on to the next one. At the end it
# prints the table of doc/coarsening.md and the targets each scene state
# meets (scripts/compare_table.py) for the scenes with results, also into
# output/compare/table.md, and exits with 1 if a run failed. Not part of the
# tests: the whole set takes 12 to 35 minutes on a 2-core machine (eight
# queues of 11.8 to 34.5 minutes; the three slowest fitted the database, the
# slowest of them on a day the host ran everything slower).
#
#   scripts/compare_scenes.sh                  # every scene
#   scripts/compare_scenes.sh bending twisting # some of them
#   EXTRA='--set "Comparison/Fine direct solver limit=40000"' scripts/compare_scenes.sh
set -euo pipefail
cd "$(dirname "$0")/.."
grep -q "^CMAKE_BUILD_TYPE:STRING=Release$" build/CMakeCache.txt 2>/dev/null || {
  echo "Error: build/ is not a Release build (scripts/setup.sh makes one)." >&2
  exit 1
}
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(pushing bending twisting buckling fibers \
                                   bridge bridge_arch shoe_sole character)
# A scene is a file prm/<scene>.prm; a name is never parsed as shell code.
for s in "${scenes[@]}"; do
  if [[ "$s" == */* || ! -f "prm/$s.prm" ]]; then
    echo "Error: no scene '$s': a scene is the name of a file prm/<scene>.prm" \
      "(pushing, bending, ...)." >&2
    exit 1
  fi
done
# EXTRA's words, with their quotes: the settings every run gets. Python's
# shlex splits them and quotes each one again, so the eval below expands
# and runs nothing.
quoted=$(python3 -c 'import shlex, sys
try:
    words = shlex.split(sys.argv[1])
except ValueError as error:
    sys.exit(f"Error: EXTRA is not a list of shell words ({error}): {sys.argv[1]}")
print(" ".join(shlex.quote(word) for word in words))' "${EXTRA:-}")
eval "extra=($quoted)"
failed=()
with_results=()
for s in "${scenes[@]}"; do
  echo "=== $s"
  # An earlier run's results must not stand in for a run that fails on its
  # input (which writes nothing): neither its tables nor its plot.
  for f in comparison.json comparison.csv error_vs_time.dat \
    error_vs_time.gnuplot error_vs_time.png; do
    rm -f "output/compare/$s/$f"
  done
  # The last --set of a parameter counts: EXTRA may change the VTU output,
  # not the run type or the directory this script reads.
  build/ddfem "prm/$s.prm" --set "Output/Write VTU=last step" "${extra[@]}" \
    --set "Run type=compare" \
    --set "Output/Output directory=output/compare/$s" || failed+=("$s")
  [ ! -f "output/compare/$s/comparison.json" ] || with_results+=("$s")
done
table_failed=0
if [ ${#with_results[@]} -gt 0 ]; then
  mkdir -p output/compare
  # The table of an earlier run stays unless this one is complete.
  if python3 scripts/compare_table.py output/compare "${with_results[@]}" \
    > output/compare/table.md.partial; then
    mv output/compare/table.md.partial output/compare/table.md
    cat output/compare/table.md
  else
    rm -f output/compare/table.md.partial
    table_failed=1
  fi
fi
if [ ${#failed[@]} -gt 0 ]; then
  echo "compare runs that exited with an error: ${failed[*]}" >&2
fi
if [ $table_failed -ne 0 ]; then
  echo "scripts/compare_table.py failed on the results of: ${with_results[*]}" >&2
fi
[ ${#failed[@]} -eq 0 ] && [ $table_failed -eq 0 ]
