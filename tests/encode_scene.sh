#!/bin/bash
# encode_scene.sh KIND SCENE.prm OUT.prm: writes SCENE.prm to OUT.prm in another
# encoding or with other line ends, or OUT.prm that includes such a file
# (OUT.prm.inc), for the tests of the parameter-file checks. KIND:
#   cr-only      CR-only line ends (classic Mac OS)
#   crlf         CRLF line ends (Windows)
#   utf8-bom     UTF-8 with a byte-order mark
#   utf16        UTF-16 with a byte-order mark
#   utf16le      UTF-16LE without a byte-order mark
#   include-*    OUT.prm is 'include OUT.prm.inc', the scene in the kind after
#                'include-' (or 'binary': bytes with NULs) in OUT.prm.inc
kind=$1 scene=$2 out=$3
case $kind in
  include-binary)
    printf 'subsection Geometry\000\001\002\n' > "$out.inc"
    printf 'include %s\n' "$(basename "$out").inc" > "$out"
    exit ;;
  include-*)
    "$0" "${kind#include-}" "$scene" "$out.inc" || exit 1
    printf 'include %s\n' "$(basename "$out").inc" > "$out"
    exit ;;
  cr-only) tr '\n' '\r' < "$scene" > "$out" ;;
  crlf) sed 's/$/\r/' "$scene" > "$out" ;;
  utf8-bom) { printf '\357\273\277'; cat "$scene"; } > "$out" ;;
  utf16) iconv -f UTF-8 -t UTF-16 "$scene" > "$out" ;;
  utf16le) iconv -f UTF-8 -t UTF-16LE "$scene" > "$out" ;;
  *) echo "encode_scene.sh: unknown kind '$kind'" >&2; exit 1 ;;
esac
