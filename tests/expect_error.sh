#!/bin/bash
# expect_error.sh BINARY SCENE.prm EXPECTED [check]: the run must stop with exit
# code 1, print exactly one line to stderr containing EXPECTED, and write nothing
# else. With 'check', --check must refuse the file too (the parameters alone
# show the problem).
binary=$1 scene=$2 expected=$3 check_must_refuse=${4:-}
dir=$(mktemp -d) && cd "$dir" || exit 1
trap 'rm -rf "$dir" "$TMPDIR"' EXIT
# Its own Open MPI session directory (outside the checked directory): parallel
# ctest runs must not race for one under /tmp.
TMPDIR=$(mktemp -d) && export TMPDIR
"$binary" "$scene" > stdout.txt 2> stderr.txt
status=$?
if [ $status -ne 1 ]; then echo "exit code $status, expected 1"; cat stderr.txt; exit 1; fi
if [ "$(wc -l < stderr.txt)" -ne 1 ]; then
  echo "stderr is not one line:"; cat stderr.txt; exit 1
fi
if LC_ALL=C grep -q '[^[:print:]]' stderr.txt; then
  echo "stderr holds control or non-ASCII bytes"; exit 1
fi
if ! grep -qF -- "$expected" stderr.txt; then
  echo "stderr does not contain '$expected':"; cat stderr.txt; exit 1
fi
if [ -s stdout.txt ]; then echo "unexpected output on stdout:"; cat stdout.txt; exit 1; fi
# --check must refuse the file with the same line, or pass it where the
# problem is one that only setting up the run finds (a mesh, a load); a
# check started without mpirun runs without MPI (source/app/main.cc).
"$binary" --check "$scene" > check_stdout.txt 2> check_stderr.txt
check_status=$?
if [ $check_status -eq 1 ]; then
  cmp -s stderr.txt check_stderr.txt ||
    { echo "--check reports another line:"; cat check_stderr.txt; exit 1; }
elif [ $check_status -ne 0 ]; then
  echo "--check: exit code $check_status"; cat check_stderr.txt; exit 1
elif [ "$check_must_refuse" = check ]; then
  echo "--check passed a file it must refuse"; exit 1
fi
rm -f check_stdout.txt check_stderr.txt
files=$(find . -type f ! -name stdout.txt ! -name stderr.txt)
if [ -n "$files" ]; then echo "files were written: $files"; exit 1; fi
directories=$(find . -mindepth 1 -type d)
if [ -n "$directories" ]; then echo "directories were made: $directories"; exit 1; fi
echo "OK: $(cat stderr.txt)"
