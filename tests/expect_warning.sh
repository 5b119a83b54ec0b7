#!/bin/bash
# expect_warning.sh BINARY SCENE.prm EXPECTED: the run must succeed (exit code
# 0) and print one warning line to stderr containing EXPECTED.
binary=$1 scene=$2 expected=$3
dir=$(mktemp -d) && cd "$dir" || exit 1
trap 'rm -rf "$dir" "$TMPDIR"' EXIT
TMPDIR=$(mktemp -d) && export TMPDIR
cp "$scene" scene.prm
"$binary" scene.prm > stdout.txt 2> stderr.txt
status=$?
if [ $status -ne 0 ]; then echo "exit code $status, expected 0"; cat stderr.txt; exit 1; fi
if [ "$(grep -c 'contact-stefan: warning: ' stderr.txt)" -ne 1 ]; then
  echo "stderr does not hold exactly one warning:"; cat stderr.txt; exit 1
fi
if ! grep -qF -- "$expected" stderr.txt; then
  echo "stderr does not contain '$expected':"; cat stderr.txt; exit 1
fi
echo "OK: $(cat stderr.txt)"
