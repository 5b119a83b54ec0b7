#!/bin/bash
# run_unit.sh EXECUTABLE REFERENCE: the unit test must exit 0 and print what
# REFERENCE holds (numdiff, relative 1e-8). UPDATE_REFERENCE=1 rewrites it.
"$1" > "$(basename "$2")" 2>&1 || { cat "$(basename "$2")"; exit 1; }
if [ "${UPDATE_REFERENCE:-0}" = 1 ]; then cp "$(basename "$2")" "$2"; exit 0; fi
numdiff -q -r 1e-8 -a 1e-12 "$2" "$(basename "$2")" > /dev/null || { numdiff -r 1e-8 -a 1e-12 "$2" "$(basename "$2")"; exit 1; }
echo "matches $2"
