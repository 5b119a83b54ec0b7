#!/bin/bash
# The section-force check on the VTU files a run writes (ctest).
#
#   run_section_force.sh BINARY SCENE.prm NP RESULTANT CELL_TOL NODAL_TOL [SET:...]
#
# Runs the scene (with the SET: entries of apply_settings.sh) on NP ranks in a
# work directory of its own, then tests/section_force.py on its output
# directory: the integral of the written stress_yy fields across every
# horizontal mesh line must be RESULTANT (N/m) within the tolerances (relative,
# on rows of equal cells; single precision in VTU).
set -u
binary=$1 scene=$2 np=$3 resultant=$4 cell_tolerance=$5 nodal_tolerance=$6
shift 6
here=$(cd "$(dirname "$0")" && pwd)
TMPDIR=$(mktemp -d) && export TMPDIR
work=$(mktemp -d "$PWD/section-force.XXXXXX") && cd "$work" || exit 1
passed=0
trap 'rm -rf "$TMPDIR"; [ "$passed" = 1 ] && rm -rf "$work"' EXIT
cp "$scene" scene.prm
"$here/apply_settings.sh" scene.prm "$@" > /dev/null || { echo "cannot apply the SET: entries"; exit 1; }
if [ "$np" -eq 1 ]; then
  "$binary" scene.prm > stdout.txt 2> stderr.txt
else
  "$here/mpirun.sh" -np "$np" "$binary" scene.prm > stdout.txt 2> stderr.txt
fi
status=$?
if [ $status -ne 0 ]; then
  echo "run failed with exit code $status"; cat stderr.txt; exit 1
fi
directory=$(sed -n 's/^ *set Directory *= *\([^ #]*\).*/\1/p' scene.prm)
/usr/bin/python3 "$here/section_force.py" "${directory:-output}" --resultant="$resultant" \
  --cell-tolerance "$cell_tolerance" --nodal-tolerance "$nodal_tolerance" && passed=1
[ "$passed" = 1 ]
