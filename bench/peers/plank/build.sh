#!/bin/sh
# Build plank's bfs_planner (Burigana & Fabiano's EPDDL toolkit, github.com/a-burigana/plank, the tool whose
# recorded times are in ../shared/benchmarks/epddl2026/expected.csv) for bench/epddl.py --plank-bin, so that
# plank and delkit are measured in the same run. Its own CMake build, Release (-O3 -DNDEBUG), one job. Needs
# cmake, g++ (C++17) and Boost.Filesystem (Debian: apt-get install cmake g++ libboost-filesystem-dev).
#
#   sh bench/peers/plank/build.sh PLANK_SRC OUT
#
# PLANK_SRC: a plank tree (CMakeLists.txt, src/, include/, external/, cmake/); OUT: the build directory
# (OUT/bfs_planner is the result). The tree is not modified.
set -eu
if [ $# -ne 2 ]; then
  echo "usage: sh build.sh PLANK_SRC OUT" >&2
  exit 2
fi
src=$(cd "$1" && pwd)
[ -f "$src/CMakeLists.txt" ] && [ -d "$src/src/frontend/bfs-planner" ] || {
  echo "build.sh: $src is not a plank source tree (CMakeLists.txt, src/frontend/bfs-planner)" >&2; exit 2; }
for tool in cmake g++; do
  command -v "$tool" >/dev/null || { echo "build.sh: $tool not found (apt-get install cmake g++ libboost-filesystem-dev)" >&2; exit 2; }
done
mkdir -p "$2"
out=$(cd "$2" && pwd)
cmake -S "$src" -B "$out" -DCMAKE_BUILD_TYPE=Release
cmake --build "$out" --target bfs_planner -j1
echo "built $out/bfs_planner"
