#!/bin/sh
# Build EFP (Fabiano et al.'s C++ epistemic forward planner, github.com/FrancescoFabiano/EFP, the tool whose
# recorded times are in ../shared/benchmarks/mastar/expected.csv) for bench/planner.py --efp-bin, so that
# EFP and delkit are measured in the same run. Its own Makefile, with -O2 instead of its default -g (as the
# issue's EFP measurement: "-O2, possibilities representation"); one job. Needs g++, bison, flex, libfl-dev
# and the Boost headers (Debian: apt-get install g++ bison flex libfl-dev libboost-dev).
#
#   sh bench/peers/efp/build.sh EFP_SRC OUT
#
# EFP_SRC: an EFP tree (its Makefile, include/, src/, lib/); OUT: a directory for the build
# (OUT/bin/efp.out is the result). The sources are copied; the tree is not modified.
set -eu
if [ $# -ne 2 ]; then
  echo "usage: sh build.sh EFP_SRC OUT" >&2
  exit 2
fi
src=$(cd "$1" && pwd)
for f in "$src/Makefile" "$src/src/main.cpp" "$src/include/parse/lcp.y"; do
  [ -f "$f" ] || { echo "build.sh: $f not found: give an EFP source tree" >&2; exit 2; }
done
for tool in g++ bison flex make; do
  command -v "$tool" >/dev/null || { echo "build.sh: $tool not found (apt-get install g++ bison flex libfl-dev libboost-dev)" >&2; exit 2; }
done
[ -d /usr/include/boost ] || { echo "build.sh: the Boost headers are missing (apt-get install libboost-dev)" >&2; exit 2; }
mkdir -p "$2"
out=$(cd "$2" && pwd)
cp -R "$src/Makefile" "$src/include" "$src/src" "$src/lib" "$out/"
cd "$out"
make -j1 MAKEFLAGS= CFLAGS="-O2 -Wall -ansi -Wfatal-errors -std=c++14 -pthread -lpthread -lrt -w"
echo "built $out/bin/efp.out"
