#!/bin/bash
# The generic plotting path of the tutorial (doc/tutorial.md): run a scene,
# then benchmarks/plot_run.py on its output directory must write both pictures.
#
#   run_plot_run.sh BINARY SCENE.prm PLOT_RUN.py
#
# Exit 77 (ctest: skipped) where Debian's matplotlib or meshio is missing.
set -u
binary=$1 scene=$2 plot=$3
/usr/bin/python3 -c 'import matplotlib, meshio' 2> /dev/null ||
  { echo "python3-matplotlib or python3-meshio is not installed: skipped"; exit 77; }
TMPDIR=$(mktemp -d) && export TMPDIR
work=$(mktemp -d "$PWD/plot_run.XXXXXX") && cd "$work" || exit 1
passed=0
trap 'rm -rf "$TMPDIR"; [ "$passed" = 1 ] && rm -rf "$work"' EXIT
"$binary" "$scene" > stdout.txt 2> stderr.txt || { echo "the run failed"; cat stderr.txt; exit 1; }
directory=$(sed -n 's/^ *set Directory *= *\([^ #]*\).*/\1/p' "$scene")
/usr/bin/python3 "$plot" "$directory" --output pictures > plot.txt 2>&1 ||
  { echo "plot_run.py failed:"; cat plot.txt; exit 1; }
for picture in fields series; do
  # A PNG of some substance: the signature and more than a blank canvas.
  file="pictures/$picture.png"
  [ -s "$file" ] && [ "$(head -c 4 "$file" | od -An -c | tr -d ' ')" = "211PNG" ] ||
    { echo "$file is missing or not a PNG"; cat plot.txt; exit 1; }
  [ "$(stat -c %s "$file")" -gt 50000 ] || { echo "$file is nearly empty"; exit 1; }
done
cat plot.txt
passed=1
