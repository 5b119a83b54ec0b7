#!/bin/bash
# resume_other_scene.sh BINARY SCENE_A SCENE_B EXPECTED
#                       [--fresh-run-between | --older-format] [SET:... ...]
# SCENE_A runs with checkpoints; SCENE_B (with the SET: entries applied) resumes
# from its checkpoint and must be refused in one line containing EXPECTED,
# naming Checkpoint/Resume, before any work: another scene (or the same one
# with other parameters) would misread the attached vectors or continue
# another history. With --fresh-run-between, SCENE_B first runs from the start
# in the same directory (which must remove SCENE_A's checkpoints). With
# --older-format, the checkpoint is made one of the format of an earlier
# version (format 2: no manifest yet).
binary=$1 scene_a=$2 scene_b=$3 expected=$4
shift 4
between=0 older=0
if [ "${1:-}" = --fresh-run-between ]; then between=1; shift; fi
if [ "${1:-}" = --older-format ]; then older=1; shift; fi
here=$(cd "$(dirname "$0")" && pwd) # (absolute: used after the cd)
dir=$(mktemp -d) && cd "$dir" || exit 1
trap 'rm -rf "$dir"' EXIT
cp "$scene_a" a.prm
settings=$here/apply_settings.sh
"$settings" a.prm "SET:Checkpoint/Interval (steps)=5" "SET:Output/Directory=$dir/out" || exit 1
"$binary" a.prm > /dev/null 2>&1 || { echo "the first scene failed"; exit 1; }
[ -f "$dir/out/checkpoint/state.txt" ] || { echo "the first scene wrote no checkpoint"; exit 1; }
if [ $older = 1 ]; then
  # What a checkpoint of format 2 looks like: no manifest, and that format in
  # state.txt. Boost's text archive writes a string as '<length> <characters>':
  # replace the whole '<length> contact-stefan checkpoint <n>' so the length
  # stays right.
  grep -q '[0-9]* contact-stefan checkpoint [0-9]*' "$dir/out/checkpoint/state.txt" ||
    { echo "no format string in the checkpoint"; exit 1; }
  sed -i 's/[0-9]* contact-stefan checkpoint [0-9]*/27 contact-stefan checkpoint 2/' \
    "$dir/out/checkpoint/state.txt"
  rm -f "$dir/out/checkpoint/manifest"
fi
cp "$scene_b" b.prm
extra=$("$settings" b.prm "$@" "SET:Output/Directory=$dir/out") || exit 1
[ -z "$extra" ] || { echo "unexpected arguments: $extra"; exit 1; }
if [ $between = 1 ]; then
  "$binary" b.prm > /dev/null 2>&1 || { echo "the fresh run failed"; exit 1; }
fi
"$settings" b.prm "SET:Checkpoint/Resume=true" || exit 1
"$here/expect_error.sh" "$binary" "$dir/b.prm" "$expected"
