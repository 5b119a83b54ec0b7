#!/bin/bash
# contact-stefan set-up on Debian (bookworm): install what is missing, build, then
#   ./setup.sh run    run the default scene (prm/subduction.prm) in build/
#   ./setup.sh test   run the whole ctest suite
#   ./setup.sh pictures  also install python3-matplotlib python3-meshio and render
#                        the scenes to doc/figures/scenes/ (doc/scenes.md)
# Needs root or sudo only when packages are missing.
set -euo pipefail
mode=${1:-run}
case $mode in run|test|pictures) ;; *) echo "usage: $0 run|test|pictures" >&2; exit 2 ;; esac
cd "$(dirname "$0")"

packages="cmake make g++ libdeal.ii-dev numdiff openmpi-bin python3"
[ "$mode" = pictures ] && packages="$packages python3-matplotlib python3-meshio"
missing=""
for p in $packages; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
    missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "Installing:$missing"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends $missing
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
cd build
if [ "$mode" = run ]; then
  ./contact-stefan ../prm/subduction.prm
elif [ "$mode" = pictures ]; then
  cmake --build . --target pictures
else
  ctest -j2 --output-on-failure
fi
