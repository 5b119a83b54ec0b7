#!/bin/bash
# resume_other_scene.sh BINARY THERMAL_SCENE MECHANICAL_SCENE: a checkpoint
# written by the thermal scene must be refused, in one line naming
# Checkpoint/Resume, by the mechanical scene resuming from it (it would
# misread the attached vectors), before any work.
binary=$1 thermal=$2 mechanical=$3
dir=$(mktemp -d) && cd "$dir" || exit 1
trap 'rm -rf "$dir"' EXIT
cp "$thermal" a.prm
printf 'subsection Checkpoint\n set Interval (steps) = 5\nend\nsubsection Output\n set Directory = %s\nend\n' \
  "$dir/out" >> a.prm
"$binary" a.prm > /dev/null 2>&1 || { echo "the thermal scene failed"; exit 1; }
cp "$mechanical" b.prm
printf 'subsection Checkpoint\n set Resume = true\nend\nsubsection Output\n set Directory = %s\nend\n' \
  "$dir/out" >> b.prm
"$(dirname "$0")/expect_error.sh" "$binary" "$dir/b.prm" \
  "parameter 'Checkpoint/Resume': cannot read '$dir/out/checkpoint/state.txt' (it was written by a scene with thermal and no mechanical fields"
