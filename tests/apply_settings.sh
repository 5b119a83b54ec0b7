#!/bin/bash
# apply_settings.sh SCENE.prm [ARGUMENT ...]: every argument of the form
# 'SET:Subsection/Entry name=value' sets that entry in SCENE.prm (replacing it
# where the file has it at top level of its subsection, appending it otherwise);
# other arguments are printed, one per line, for the caller (requirements).
# Shared by run_scene.sh and run_resume.sh, so that variants of a benchmark
# need no copies of its file.
scene=$1
shift
for argument in "$@"; do
  if [[ "$argument" == SET:* ]]; then
    entry=${argument#SET:} path=${entry%%=*} value=${entry#*=}
    section=${path%/*} key=${path##*/}
    if [[ "$section" != */* ]] && grep -q "^ *set $key *=" "$scene"; then
      sed -i "s|^\( *set $key *=\).*|\1 $value|" "$scene"
    else
      # Append, entering each level of a nested section (A/B/key); a file may
      # enter a subsection more than once.
      IFS=/ read -ra levels <<< "$section"
      for level in "${levels[@]}"; do echo "subsection $level"; done >> "$scene"
      echo "set $key = $value" >> "$scene"
      for level in "${levels[@]}"; do echo "end"; done >> "$scene"
    fi
  else
    printf '%s\n' "$argument"
  fi
done
