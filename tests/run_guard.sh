#!/bin/bash
# What protects a run's output (issue 23 section 4, doc/reliability.md), used by ctest.
#
#   run_guard.sh BINARY SCENE.prm CASE
#
# CASE is one of
#   lock    a run whose output directory is locked by another one is refused with
#           exit 1 and one line naming the directory and the process holding it;
#           the holder's output is untouched. Once the holder is gone, a run works.
#   stale   VTU/PVTU/PVD files of an earlier run (other steps, pieces of a run on
#           more ranks, an index) are removed before the first is written; the
#           index lists exactly the files of this run, and they all exist.
#   term    SIGTERM after step 3 (CONTACT_STEFAN_TERM_AFTER_STEP): exit code 143,
#           one line on stderr naming the signal, statistics rows 0-3 complete,
#           the PVD index valid and every file it names complete.
set -u
binary=$1 scene=$2 case=$3
here=$(cd "$(dirname "$0")" && pwd)
TMPDIR=$(mktemp -d) && export TMPDIR
work=$(mktemp -d "$PWD/guard-$case.XXXXXX") && cd "$work" || exit 1
trap 'rm -rf "$TMPDIR"; [ "$passed" = 1 ] && rm -rf "$work"' EXIT
passed=0
cp "$scene" scene.prm
"$here/apply_settings.sh" scene.prm "SET:Output/VTU interval=1" > /dev/null
directory=$(sed -n 's/^ *set Directory *= *\([^ #]*\).*/\1/p' scene.prm | tail -1)
directory=${directory:-output}

one_line() { # one_line FILE PATTERN: exactly one line on stderr, matching PATTERN
  [ "$(wc -l < "$1")" -eq 1 ] || { echo "expected one line on stderr, got:"; cat "$1"; return 1; }
  grep -q -- "$2" "$1" || { echo "the line does not say '$2':"; cat "$1"; return 1; }
}
check_pvd() { # every file the index names exists and is complete, none other is there
  local pvd=$directory/solution.pvd
  [ -f "$pvd" ] || { echo "no $pvd"; return 1; }
  grep -q '</VTKFile>' "$pvd" || { echo "$pvd is not complete"; return 1; }
  local listed
  listed=$(sed -n 's/.*file="\([^"]*\)".*/\1/p' "$pvd" | sort)
  for f in $listed; do
    grep -q '</VTKFile>' "$directory/$f" || { echo "$f (in the index) is missing or cut"; return 1; }
    for piece in $(sed -n 's/.*Source="\([^"]*\)".*/\1/p' "$directory/$f"); do
      grep -q '</VTKFile>' "$directory/$piece" || { echo "piece $piece is missing or cut"; return 1; }
    done
  done
  local present
  present=$(cd "$directory" && ls solution_*.pvtu 2>/dev/null | sort)
  [ "$listed" = "$present" ] ||
    { echo "the index lists '$listed' but the directory holds '$present'"; return 1; }
}

case $case in
lock)
  # First a process holding the lock the way a run does (flock on the directory).
  mkdir -p "$directory"
  # (in a process group of its own, so that flock and its sleep end together)
  setsid flock "$directory" sleep 30 &
  holder=$!
  sleep 0.5
  echo "1 2 3" > "$directory/statistics.txt"
  "$binary" scene.prm > stdout.txt 2> stderr.txt
  status=$?
  kill -- -$holder 2>/dev/null; wait $holder 2>/dev/null
  [ $status -eq 1 ] || { echo "a run into a locked directory: exit $status, expected 1"; cat stderr.txt; exit 1; }
  one_line stderr.txt "is in use by another run (process $holder)" || exit 1
  [ "$(cat "$directory/statistics.txt")" = "1 2 3" ] || { echo "the holder's statistics were touched"; exit 1; }
  # A real run holds the lock too: a second one started beside it is refused.
  cp scene.prm short.prm
  "$here/apply_settings.sh" scene.prm "SET:Time stepping/Time step=2e-6" > /dev/null
  "$binary" scene.prm > first.txt 2> first_err.txt &
  first=$!
  for i in $(seq 100); do grep -q "^Output:" first.txt 2>/dev/null && break; sleep 0.1; done
  "$binary" scene.prm > second.txt 2> second_err.txt
  status=$?
  kill -TERM $first; wait $first
  first_status=$?
  [ $status -eq 1 ] || { echo "the second run: exit $status, expected 1"; cat second_err.txt; exit 1; }
  one_line second_err.txt "is in use by another run (process $first)" || exit 1
  [ $first_status -eq 143 ] || { echo "the first run ended with $first_status after SIGTERM, expected 143"; cat first_err.txt; exit 1; }
  # The holder gone, the directory is free again.
  "$binary" short.prm > third.txt 2> third_err.txt ||
    { echo "a run after the holder ended failed"; cat third_err.txt; exit 1; }
  echo "a locked directory is refused in one line; freed, it is used again"
  ;;
stale)
  mkdir -p "$directory"
  for f in solution_00099.pvtu solution_00099.0.vtu solution_00000.3.vtu solution_00001.1.vtu; do
    echo '<VTKFile>earlier run</VTKFile>' > "$directory/$f"
  done
  echo '<VTKFile><Collection><DataSet timestep="9" file="solution_00099.pvtu"/></Collection></VTKFile>' > "$directory/solution.pvd"
  echo keep > "$directory/notes.txt"
  "$binary" scene.prm > stdout.txt 2> stderr.txt || { echo "the run failed"; cat stderr.txt; exit 1; }
  grep -q "removed 5 VTU/PVD files of an earlier run" stdout.txt ||
    { echo "the run does not say that it removed the earlier files:"; grep '^Output' stdout.txt; exit 1; }
  for f in solution_00099.pvtu solution_00099.0.vtu solution_00000.3.vtu solution_00001.1.vtu; do
    [ ! -e "$directory/$f" ] || { echo "$f of the earlier run is still there"; exit 1; }
  done
  [ -f "$directory/notes.txt" ] || { echo "a file that is not output was removed"; exit 1; }
  check_pvd || exit 1
  echo "the earlier run's files are gone, the index is this run's"
  ;;
term)
  CONTACT_STEFAN_TERM_AFTER_STEP=3 "$binary" scene.prm > stdout.txt 2> stderr.txt
  status=$?
  [ $status -eq 143 ] || { echo "exit $status after SIGTERM, expected 143"; cat stderr.txt; exit 1; }
  one_line stderr.txt "stopped by SIGTERM after step 3" || exit 1
  rows=$(grep -v '^#' "$directory/statistics.txt" | tail -n +2 | wc -l)
  [ "$rows" -eq 4 ] || { echo "$rows statistics rows, expected 4 (steps 0-3)"; exit 1; }
  awk '/^#/ { next } !names++ { n = NF } NF != n { exit 1 }' "$directory/statistics.txt" ||
    { echo "a statistics row is incomplete"; exit 1; }
  check_pvd || exit 1
  [ ! -d "$directory/checkpoint" ] || { echo "a checkpoint although checkpoints are off"; exit 1; }
  # With checkpoints on (none due at step 3) the stop writes one, and --resume
  # finishes the run: all 21 rows, the exact stresses, a valid index.
  "$here/apply_settings.sh" scene.prm "SET:Checkpoint/Interval (steps)=100" > /dev/null
  CONTACT_STEFAN_TERM_AFTER_STEP=3 "$binary" scene.prm > stdout2.txt 2> stderr2.txt
  status=$?
  [ $status -eq 143 ] || { echo "exit $status after SIGTERM with checkpoints, expected 143"; cat stderr2.txt; exit 1; }
  one_line stderr2.txt "and --resume continues from there" || exit 1
  "$binary" --resume scene.prm > resumed.txt 2> resumed_err.txt ||
    { echo "the resume after SIGTERM failed"; cat resumed_err.txt; exit 1; }
  grep -q "^Resumed from .* at step 3," resumed.txt || { echo "not resumed at step 3"; exit 1; }
  rows=$(grep -v '^#' "$directory/statistics.txt" | tail -n +2 | wc -l)
  [ "$rows" -eq 21 ] || { echo "$rows statistics rows after the resume, expected 21"; exit 1; }
  error=$(sed -n 's/^RESULT max relative stress L2 error = //p' resumed.txt)
  awk -v e="$error" 'BEGIN { exit !(e != "" && e < 1e-10) }' ||
    { echo "stress error after the resume: '$error'"; exit 1; }
  check_pvd || exit 1
  echo "stopped after step 3 with exit 143, output complete; with checkpoints resumed exactly"
  ;;
*) echo "unknown case '$case'"; exit 1 ;;
esac
passed=1
