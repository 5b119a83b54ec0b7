#!/bin/bash
# resume_damaged.sh BINARY SCENE.prm NP EXPECTED MUTATION [SET:... | OTHER:... ...]
#
# A damaged checkpoint must be refused before anything of it is read: the scene
# (with the SET: entries applied; it must write checkpoints) runs on NP ranks,
# killed after step 7 and resumed to its end (so that there is a checkpoint of
# an earlier step of the same run, copied aside); the last checkpoint is
# damaged by MUTATION, and the resume must exit with code 1, print exactly one
# line containing EXPECTED (no control bytes), and leave the output directory
# unchanged, byte for byte. MUTATION is one of
#   empty:FILE  half:FILE  delete:FILE  flip:FILE (its middle byte inverted)
#   digit:FILE  (the first digit after its middle changed)
#   older:FILE  (the same file of the earlier checkpoint of the same run)
#   other:FILE  (the same file of a run with the OTHER:Path=value entries)
#   forge-time  (the time in state.txt 1 % later, the manifest written anew:
#                only the check of the values read back can refuse it)
#   old-hint:FILE  (FILE flipped, with the earlier checkpoint as checkpoint.old)
#   mesh-file:MESH (the scene's mesh, a copy of MESH, changed after the run)
#   new-only    (a run killed while writing its first checkpoint)
set -u
binary=$1 scene=$2 np=$3 expected=$4 mutation=$5
shift 5
here=$(cd "$(dirname "$0")" && pwd)
TMPDIR=$(mktemp -d) && export TMPDIR
work=$(mktemp -d "$PWD/damaged.XXXXXX") && cd "$work" || exit 1
trap 'rm -rf "$TMPDIR"; [ "$passed" = 1 ] && rm -rf "$work"' EXIT
passed=0
sets=() others=()
for argument in "$@"; do
  case "$argument" in
    SET:*) sets+=("$argument") ;;
    OTHER:*) others+=("SET:${argument#OTHER:}") ;;
    *) echo "unexpected argument: $argument"; exit 1 ;;
  esac
done
cp "$scene" scene.prm
"$here/apply_settings.sh" scene.prm "${sets[@]}" "SET:Output/Directory=out" \
  "SET:Output/VTU interval=0" > /dev/null
grep -q "Interval (steps)" scene.prm || { echo "the scene writes no checkpoints"; exit 1; }
kind=${mutation%%:*} file=${mutation#*:}
if [ "$kind" = mesh-file ]; then
  cp "$file" mesh.msh && file=mesh.msh
  "$here/apply_settings.sh" scene.prm "SET:Geometry/Mesh file=mesh.msh" > /dev/null
fi

run() { # run [OPTION]: in the current directory, on NP ranks
  if [ "$np" -eq 1 ]; then
    "$binary" "$@" scene.prm
  else
    # (--quiet: without the launcher's own lines about a rank's exit code)
    "$here/mpirun.sh" --quiet -np "$np" "$binary" "$@" scene.prm
  fi
}

if [ "$kind" = new-only ]; then
  CONTACT_STEFAN_KILL_DURING_CHECKPOINT=3 run > stdout.txt 2> stderr.txt &&
    { echo "the run was not killed"; exit 1; }
  [ -d out/checkpoint.new ] && [ ! -e out/checkpoint ] ||
    { echo "no checkpoint.new alone"; exit 1; }
else
  CONTACT_STEFAN_KILL_AFTER_STEP=7 run > stdout.txt 2> stderr.txt &&
    { echo "the run was not killed"; exit 1; }
  cp -r out/checkpoint older
  run --resume > stdout.txt 2> stderr.txt || { echo "the resume failed"; cat stderr.txt; exit 1; }
fi
c=out/checkpoint
flip() { # flip FILE: invert its middle byte
  local size offset byte
  size=$(stat -c %s "$1") offset=$((size / 2))
  byte=$(od -An -tu1 -j "$offset" -N1 "$1" | tr -d ' ')
  printf "\\$(printf %03o $((byte ^ 255)))" |
    dd of="$1" bs=1 seek="$offset" conv=notrunc status=none
}
case "$kind" in
  empty) : > "$c/$file" ;;
  half) truncate -s $(($(stat -c %s "$c/$file") / 2)) "$c/$file" ;;
  delete) rm "$c/$file" ;;
  flip) flip "$c/$file" ;;
  digit)
    size=$(stat -c %s "$c/$file")
    head -c $((size / 2)) "$c/$file" > first
    tail -c +$((size / 2 + 1)) "$c/$file" | sed '0,/[0-9]/{s/[0-8]/9/;t;s/9/1/}' > second
    cat first second > "$c/$file" ;;
  older) cp "older/$file" "$c/$file" ;;
  other)
    mkdir other && cp scene.prm other/ && cd other &&
      "$here/apply_settings.sh" scene.prm "${others[@]}" > /dev/null &&
      { run > stdout.txt 2> stderr.txt || { echo "the other run failed"; exit 1; }; } && cd .. &&
      cp "other/$c/$file" "$c/$file" ;;
  forge-time)
    awk '{ for (i = 1; i <= NF; ++i) if ($i ~ /^[0-9.]+e[-+][0-9]+$/ && !done) {
             # (the first number in scientific notation: the time)
             $i = sprintf("%.17e", $i * 1.01); done = 1 } print }' "$c/state.txt" > state &&
      mv state "$c/state.txt"
    /usr/bin/python3 "$here/mutation_checkpoint.py" --rewrite-manifest "$c" ;;
  old-hint) cp -r older "$c.old" && flip "$c/$file" ;;
  mesh-file) sed -i '0,/^12 2 1 0$/s//12 2.1 1 0/' mesh.msh ;;
  new-only) ;;
  *) echo "unknown mutation $mutation"; exit 1 ;;
esac
before=$(find out -type f -exec md5sum {} + | sort)
run --resume > stdout.txt 2> stderr.txt
status=$?
[ $status -eq 1 ] || { echo "exit code $status, expected 1"; cat stderr.txt; exit 1; }
[ "$(wc -l < stderr.txt)" -eq 1 ] || { echo "stderr is not one line:"; cat stderr.txt; exit 1; }
if LC_ALL=C grep -q '[^[:print:]]' stderr.txt; then
  echo "stderr holds control or non-ASCII bytes"; exit 1
fi
grep -qF -- "$expected" stderr.txt ||
  { echo "stderr does not contain '$expected':"; cat stderr.txt; exit 1; }
[ "$(find out -type f -exec md5sum {} + | sort)" = "$before" ] ||
  { echo "the refused resume changed the output directory"; exit 1; }
echo "OK: $(cat stderr.txt)"
passed=1
