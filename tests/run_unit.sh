#!/bin/bash
# run_unit.sh EXECUTABLE REFERENCE [NP [ARGUMENT ...]]: the test program, run on
# NP MPI ranks (default 1: without mpirun) with the given arguments, must exit 0
# and print what REFERENCE holds (numdiff, relative 1e-8).
# UPDATE_REFERENCE=1 rewrites the reference instead.
set -u
here=$(cd "$(dirname "$0")" && pwd)
binary=$1 reference=$2 np=${3:-1}
shift $(( $# < 3 ? $# : 3 ))
# Each test gets its own Open MPI session directory: parallel ctest runs must
# not race for one under /tmp.
TMPDIR=$(mktemp -d) && export TMPDIR
trap 'rm -rf "$TMPDIR"' EXIT
out=$(basename "$reference" .output)-np$np.out
if [ "$np" -eq 1 ]; then
  "$binary" "$@" > "$out" 2>&1
else
  "$here/mpirun.sh" -np "$np" "$binary" "$@" > "$out" 2>&1
fi || { cat "$out"; exit 1; }
if [ "${UPDATE_REFERENCE:-0}" = 1 ]; then cp "$out" "$reference"; exit 0; fi
numdiff -q -r 1e-8 -a 1e-12 "$reference" "$out" > /dev/null ||
  { numdiff -r 1e-8 -a 1e-12 "$reference" "$out"; exit 1; }
echo "matches $reference"
