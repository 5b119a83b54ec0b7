#!/bin/bash
# Serial runs side by side (ctest cli/concurrent-serial-runs):
#   check_concurrent_serial.sh BINARY SCENE.prm
# Open MPI gives every daemon-less singleton the same session directory
# (jf.0/1), and each removes it at MPI_Finalize; a serial run that opened a file
# by MPI-IO (a checkpoint) after another serial run had ended found it gone
# (app/mpi_start.h). Here run A writes a checkpoint per step; once its first
# checkpoint exists it is held (SIGSTOP) while run B starts and ends, then it
# goes on and must write more checkpoints, end with exit code 0 and print no
# Open MPI complaint. Run A is held to Open MPI's shared-file-pointer component
# sm, the one that puts a file into the session directory at every
# MPI_File_open, so that the check means the same whatever the environment
# would select; without the directory, Open MPI 4.1 prints "unable to open file
# for mmap" and goes on without a shared file pointer (exit code 0), which the
# check of run A's output catches. A TMPDIR of its own keeps the other tests'
# runs out.
set -u
binary=$1 scene=$2
here=$(cd "$(dirname "$0")" && pwd)
unset OMPI_MCA_orte_jobfam_session_dir OMPI_MCA_orte_tmpdir_base OMPI_MCA_ess_singleton_isolated \
  OMPI_MCA_io OMPI_MCA_sharedfp CONTACT_STEFAN_SERIAL_MPI
work=$(mktemp -d "$PWD/concurrent.XXXXXX") && cd "$work" || exit 1
TMPDIR=$(mktemp -d) && export TMPDIR
passed=0
a_pid=
trap '[ -n "$a_pid" ] && kill -9 "$a_pid" 2> /dev/null; rm -rf "$TMPDIR";
      [ "$passed" = 1 ] && rm -rf "$work"' EXIT
trap 'exit 1' TERM INT
for run in A B; do
  cp "$scene" "$run.prm"
  "$here/apply_settings.sh" "$run.prm" "SET:Output/Directory=out$run" > /dev/null || exit 1
done
# (steps 30 times shorter: hundreds of steps, so that run A is still going
# when its first checkpoint is seen)
tau=$(awk -F= '/^ *set Time step *=/ { print $2 * 1 / 30; exit }' "$scene")
"$here/apply_settings.sh" A.prm "SET:Checkpoint/Interval (steps)=1" \
  "SET:Time stepping/Time step=$tau" > /dev/null || exit 1
OMPI_MCA_sharedfp=sm "$binary" A.prm > A.txt 2>&1 &
a_pid=$!
for _ in $(seq 600); do
  [ -d outA/checkpoint ] && break
  kill -0 "$a_pid" 2> /dev/null || break
  sleep 0.05
done
if ! kill -STOP "$a_pid" 2> /dev/null || [ ! -d outA/checkpoint ]; then
  echo "FAIL run A ended or wrote no checkpoint before run B could start"; cat A.txt; exit 1
fi
steps_before=$(grep -c '^Step ' A.txt)
timeout 120 "$binary" B.prm > B.txt 2>&1
b_code=$?
kill -CONT "$a_pid"
wait "$a_pid"
a_code=$?
a_pid=
steps_after=$(grep -c '^Step ' A.txt)
failed=0
[ "$b_code" = 0 ] || { echo "FAIL run B: exit code $b_code"; tail -3 B.txt; failed=1; }
[ "$a_code" = 0 ] || { echo "FAIL run A: exit code $a_code"; failed=1; }
[ "$steps_after" -gt $((steps_before + 1)) ] ||
  { echo "FAIL run A took no step after run B ended ($steps_before, then $steps_after)"; failed=1; }
if grep -E 'mca_|unable to open|MPI_ERR|Abort' A.txt; then
  echo "FAIL run A printed the lines above"; failed=1
fi
echo "run A: $steps_before steps before run B, $steps_after in all, exit code $a_code; run B: exit code $b_code"
# Both runs ended: each run's session directory is gone (only their parent,
# made by the program, stays).
parent="$TMPDIR/contact-stefan-mpi.$(id -u)"
if [ -n "$(ls -A "$parent" 2> /dev/null)" ]; then
  echo "FAIL session directories left behind: $(ls -A "$parent")"; failed=1
fi
[ "$failed" = 0 ] && passed=1
[ "$passed" = 1 ]
