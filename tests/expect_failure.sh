#!/bin/bash
# expect_failure.sh BINARY SCENE.prm CODE EXPECTED: a run that fails part way
# (bad data at a later time) must stop with exit code CODE, print exactly one
# line to stderr containing EXPECTED, and leave complete output: every line of
# the statistics table has the header's number of columns, and no NaN or
# infinity appears in stdout or in the table.
# An optional fifth argument NP runs it on NP MPI ranks: a failure that every
# rank finds must still be one line (printed by rank 0).
binary=$1 scene=$2 code=$3 expected=$4 np=${5:-1}
if ! [[ "$code" =~ ^[0-9]+$ ]] || [ -z "$expected" ]; then
  echo "the scene needs '# EXPECT-EXIT: code' and '# EXPECT: text' lines"; exit 1
fi
# This script's directory, absolute: the helpers beside it are called
# after the cd below.
here=$(cd "$(dirname "$0")" && pwd)
dir=$(mktemp -d) && cd "$dir" || exit 1
trap 'rm -rf "$dir" "$TMPDIR"' EXIT
TMPDIR=$(mktemp -d) && export TMPDIR
if [ "$np" -eq 1 ]; then
  "$binary" "$scene" > stdout.txt 2> stderr.txt
else
  "$here/mpirun.sh" --quiet -np "$np" "$binary" "$scene" \
    > stdout.txt 2> stderr.txt
fi
status=$?
if [ $status -ne "$code" ]; then echo "exit code $status, expected $code"; cat stderr.txt; exit 1; fi
if [ "$(wc -l < stderr.txt)" -ne 1 ]; then
  echo "stderr is not one line:"; cat stderr.txt; exit 1
fi
if ! grep -qF -- "$expected" stderr.txt; then
  echo "stderr does not contain '$expected':"; cat stderr.txt; exit 1
fi
table=$(find . -name statistics.txt | head -1)
# The header, step 0 and at least one step before the failure.
if [ -z "$table" ] || [ "$(grep -vc '^#' "$table")" -lt 3 ]; then
  echo "no statistics rows of steps before the failure"; exit 1
fi
if ! awk '/^#/ { next } !names++ { n = NF } NF != n { exit 1 }' "$table"; then
  echo "incomplete statistics row:"; cat "$table"; exit 1
fi
if grep -qiE '(^|[^a-z])(nan|inf)([^a-z]|$)' stdout.txt "$table"; then
  echo "a non-finite number reached the output:"; grep -iE 'nan|inf' stdout.txt "$table"; exit 1
fi
echo "OK: $(cat stderr.txt)"
