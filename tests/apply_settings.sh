#!/bin/bash
# apply_settings.sh SCENE.prm [ARGUMENT ...]: every argument of the form
# 'SET:Subsection/Entry name=value' sets that entry in SCENE.prm (replacing the
# lines that set it in that subsection path, appending it if there are none: an
# entry may be set only once; '<semicolon>' in a value stands for ';'); other arguments
# are printed, one per line, for
# the caller (requirements). Shared by run_scene.sh, run_resume.sh and
# resume_other_scene.sh, so that variants of a benchmark need no copies of its
# file.
scene=$1
shift
for argument in "$@"; do
  if [[ "$argument" == SET:* ]]; then
    entry=${argument#SET:} path=${entry%%=*} value=${entry#*=}
    # '<semicolon>' stands for ';' (a ';' would split the argument in CMake's lists on
    # its way from tests/cmake/*.cmake to the test).
    value=${value//'<semicolon>'/;}
    section=${path%/*} key=${path##*/}
    # The subsection path of each line as deal.II reads it (a comment from
    # '#' on, 'subsection'/'end' nest); raw values through the environment.
    SECTION=$section KEY=$key VALUE=$value awk '
      function trim(s) { sub(/^[ \t]+/, "", s); sub(/[ \t]+$/, "", s); return s }
      { line = $0; sub(/#.*/, "", line); gsub(/\t/, " ", line); line = trim(line) }
      line ~ /^(subsection|SUBSECTION) / { stack[++depth] = trim(substr(line, 12)); print; next }
      line ~ /^(end|END) *$/ { if (depth > 0) depth--; print; next }
      line ~ /^(set|SET) / && index(line, "=") > 0 {
        name = trim(substr(line, 5, index(line, "=") - 5)); path = ""
        for (k = 1; k <= depth; k++) path = path (k > 1 ? "/" : "") stack[k]
        if (path == ENVIRON["SECTION"] && name == ENVIRON["KEY"]) {
          match($0, /^[ \t]*/)
          print substr($0, 1, RLENGTH) "set " ENVIRON["KEY"] " = " ENVIRON["VALUE"]
          found = 1; next
        }
      }
      { print }
      END { exit found ? 0 : 3 }' "$scene" > "$scene.new"
    status=$?
    mv "$scene.new" "$scene"
    if [ $status -eq 3 ]; then
      # Append, entering each level of a nested section (A/B/key).
      IFS=/ read -ra levels <<< "$section"
      for level in "${levels[@]}"; do echo "subsection $level"; done >> "$scene"
      printf 'set %s = %s\n' "$key" "$value" >> "$scene"
      for level in "${levels[@]}"; do echo "end"; done >> "$scene"
    elif [ $status -ne 0 ]; then
      exit 1
    fi
  else
    printf '%s\n' "$argument"
  fi
done
