#!/bin/bash
# copy_scene.sh SCENE.prm COPY.prm: copies a scene for a test's own directory,
# with each relative 'include' made absolute (an included file's name is
# relative to the including file's directory, which the copy has left).
set -eu
source=$1 copy=$2
directory=$(cd "$(dirname "$source")" && pwd)
sed -E "s#^([[:space:]]*include[[:space:]]+)([^/[:space:]][^[:space:]]*)#\1$directory/\2#" \
  "$source" > "$copy"
