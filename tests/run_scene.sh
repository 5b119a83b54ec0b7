#!/bin/bash
# Regression run of one scene, used by ctest.
#
#   run_scene.sh BINARY SCENE.prm REFERENCE NP [REQUIREMENT ...]
#
# Arguments 'SET:Subsection/Entry name=value' set that entry in the copy of the
# scene the test runs (replacing it where the file has it, adding it otherwise),
# so that variants of a benchmark need no copies of its file.
# Runs the scene on NP MPI ranks in the current directory, keeps the deterministic
# part of what it printed (the RESULT lines except the wall time, and the
# statistics table without its wall_time column), compares that with REFERENCE
# by numdiff, and checks each REQUIREMENT of the form 'RESULT name<value' or
# 'RESULT name>value' against the exact-solution numbers of this run, and each
# of the form 'WARNING text': the run printed exactly one warning line to
# stderr, and it contains text.
# The linear solvers' work ('RESULT ... solver: ...', CG iterations and AMG
# set-ups) depends on the preconditioner's settings and the partition, which
# variants sharing a reference differ in: it is checked by requirements only.
# An argument 'IGNORE:RESULT name' leaves that RESULT line out of the
# comparison on both sides (a variant that shares a reference but counts
# differently by design, e.g. factorisations: KLU keeps every factor for
# recall, CHOLMOD modifies some in place); its value is then checked by
# requirements, and such a test never rewrites the reference (with
# UPDATE_REFERENCE=1 it passes without writing). 'IGNORE:column name' does the
# same for a column of the statistics table (a quantity that is negligible in
# the scene and whose digits depend on the rank count, e.g. the subduction
# zone's contact work on 2 ranks).
# With UPDATE_REFERENCE=1 the reference is rewritten instead (after the
# requirements pass): references are produced by the code, never by hand.
set -u
binary=$1 scene=$2 reference=$3 np=$4
shift 4
name=$(basename "$reference" .output)
# Each test gets its own Open MPI session directory: parallel ctest runs must
# not race for one under /tmp.
TMPDIR=$(mktemp -d) && export TMPDIR
out=$name.out
# A work directory of its own: several tests share a reference (serial and
# parallel, variants of one scene) and run at the same time under ctest -j.
# It is kept when the test fails, removed when it passes.
# This script's directory, absolute: the helpers beside it are called
# after the cd below.
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d "$PWD/$name.XXXXXX") && cd "$work" || exit 1
trap 'rm -rf "$TMPDIR"; [ "$passed" = 1 ] && rm -rf "$work"' EXIT
passed=0
"$here/copy_scene.sh" "$scene" scene.prm
requirements=()
listed=$("$here/apply_settings.sh" scene.prm "$@") ||
  { echo "cannot apply the SET: entries"; exit 1; }
while IFS= read -r requirement; do
  [ -z "$requirement" ] || requirements+=("$requirement")
done <<< "$listed"
scene=scene.prm

if [ "$np" -eq 1 ]; then
  "$binary" "$scene" > stdout.txt 2> stderr.txt
else
  "$here/mpirun.sh" -np "$np" "$binary" "$scene" > stdout.txt 2> stderr.txt
fi
status=$?
if [ $status -ne 0 ]; then
  echo "run failed with exit code $status"; cat stderr.txt; tail -20 stdout.txt; exit 1
fi

statistics=$(sed -n 's/^ *set Statistics file *= *\([^ #]*\).*/\1/p' "$scene")
directory=$(sed -n 's/^ *set Directory *= *\([^ #]*\).*/\1/p' "$scene")
statistics=${statistics:-statistics.txt} directory=${directory:-output}
if [ ! -s "$directory/$statistics" ]; then
  echo "the run wrote no statistics table at $directory/$statistics"; exit 1
fi
{
  grep '^RESULT' stdout.txt | grep -v 'RESULT wall time'
  awk '/^#/ { next }
       !names++ { for (i = 1; i <= NF; ++i) if ($i != "wall_time") keep[i] = 1 }
       { line = ""
         for (i = 1; i <= NF; ++i) if (i in keep) line = line (line == "" ? "" : " ") $i
         print line }' \
      "$directory/$statistics"
} > "$out.all"
grep -v '^RESULT [a-z]* solver: ' "$out.all" > "$out"

failed=0
ignored=()
ignored_columns=()
for requirement in "${requirements[@]}"; do
  if [[ "$requirement" =~ ^IGNORE:(RESULT .*)$ ]]; then
    ignored+=("${BASH_REMATCH[1]} = ")
  elif [[ "$requirement" =~ ^IGNORE:column\ ([A-Za-z0-9_.-]+)$ ]]; then
    ignored_columns+=("${BASH_REMATCH[1]}")
  elif [[ "$requirement" =~ ^RESULT\ (.*)([\<\>])(.*)$ ]]; then
    key=${BASH_REMATCH[1]} op=${BASH_REMATCH[2]} bound=${BASH_REMATCH[3]}
    value=$(sed -n "s/^RESULT $key = //p" "$out.all")
    if [ -z "$value" ]; then
      echo "requirement '$requirement': no RESULT line '$key'"; failed=1; continue
    fi
    if ! [[ "$value" =~ ^[-+]?[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?$ ]]; then
      echo "requirement '$requirement': '$value' is not a number"; failed=1; continue
    fi
    if ! awk -v v="$value" -v b="$bound" -v op="$op" \
         'BEGIN { exit !(op == "<" ? v < b : v > b) }'; then
      echo "requirement failed: $key = $value, required $op $bound"; failed=1
    else
      echo "requirement met: $key = $value $op $bound"
    fi
  elif [[ "$requirement" =~ ^WARNING\ (.*)$ ]]; then
    text=${BASH_REMATCH[1]}
    warnings=$(grep -c 'contact-stefan: warning: ' stderr.txt)
    if [ "$warnings" -ne 1 ]; then
      echo "requirement '$requirement': $warnings warning lines on stderr, expected 1"
      cat stderr.txt; failed=1
    elif ! grep 'contact-stefan: warning: ' stderr.txt | grep -qF -- "$text"; then
      echo "requirement '$requirement': the warning does not contain it:"; cat stderr.txt
      failed=1
    else
      echo "requirement met: $(grep 'contact-stefan: warning: ' stderr.txt)"
    fi
  else
    echo "malformed requirement '$requirement'"; failed=1
  fi
done
[ $failed -eq 0 ] || exit 1

if [ "${UPDATE_REFERENCE:-0}" = 1 ]; then
  if [ $((${#ignored[@]} + ${#ignored_columns[@]})) -gt 0 ]; then
    echo "reference $reference not written: this test leaves lines or columns of it out"
    passed=1; exit 0
  fi
  cp "$out" "$reference"; echo "reference $reference written"; passed=1; exit 0
fi
expected=$reference
if [ ${#ignored[@]} -gt 0 ]; then
  printf '%s\n' "${ignored[@]}" > ignored.txt
  for line in "${ignored[@]}"; do
    grep -qF -- "$line" "$reference" ||
      { echo "IGNORE:${line% = }: no such line in $reference"; exit 1; }
  done
  grep -vF -f ignored.txt "$reference" > expected.txt
  grep -vF -f ignored.txt "$out" > "$out.compared" && mv "$out.compared" "$out"
  expected=expected.txt
fi
if [ ${#ignored_columns[@]} -gt 0 ]; then
  # The statistics table's header is the first line that is not a RESULT line;
  # a column it does not name is refused (as an unknown IGNORE: line is).
  drop_columns() {
    awk -v names="${ignored_columns[*]}" '
      BEGIN { wanted = split(names, n, " "); for (i = 1; i <= wanted; ++i) drop[n[i]] = 1 }
      /^RESULT / { print; next }
      !header++ { for (i = 1; i <= NF; ++i) if ($i in drop) { skip[i] = 1; ++found } }
      { line = ""
        for (i = 1; i <= NF; ++i) if (!(i in skip)) line = line (line == "" ? "" : " ") $i
        print line }
      END { exit found != wanted }' "$1" > "$1.columns" && mv "$1.columns" "$1"
  }
  [ "$expected" = expected.txt ] || { cp "$reference" expected.txt; expected=expected.txt; }
  drop_columns expected.txt && drop_columns "$out" ||
    { echo "IGNORE:column ${ignored_columns[*]}: not a column of the statistics table of $reference and this run"; exit 1; }
fi
# Relative 1e-6 and absolute 1e-9 (energy residuals are round-off, ~1e-14).
numdiff -q -r 1e-6 -a 1e-9 -s ' \t\n=' "$expected" "$out" > /dev/null || {
  numdiff -r 1e-6 -a 1e-9 -s ' \t\n=' "$expected" "$out" | head -30; exit 1; }
echo "matches $reference"
passed=1
