#!/bin/sh
# Build SMCDEL's side of bench/symbolic.py --smcdel-bin (see README.md here): HasCacBDD as a package of
# its own (its Setup.hs compiles the bundled CacBDD C++ sources), then SmcdelBench.hs together with the
# SMCDEL library modules it imports, with GHC alone (no Hackage: every other dependency is a Debian
# libghc-*-dev package).  Single job throughout.
#
#   sh bench/peers/smcdel/build.sh SMCDEL_SRC HASCACBDD_SRC OUT
#
# SMCDEL_SRC: an SMCDEL v1.3.0 tree; HASCACBDD_SRC: a HasCacBDD v0.2.0.0 tree (the version SMCDEL 1.3.0's
# stack.yaml pins); OUT: a directory for the build (OUT/bin/smcdel-bench is the result).
set -eu
if [ $# -ne 3 ]; then
  echo "usage: sh build.sh SMCDEL_SRC HASCACBDD_SRC OUT" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
smcdel=$(cd "$1" && pwd)
cacbdd=$(cd "$2" && pwd)
mkdir -p "$3"
out=$(cd "$3" && pwd)
for f in "$smcdel/src/SMCDEL/Symbolic/S5.hs" "$cacbdd/HasCacBDD.cabal"; do
  [ -f "$f" ] || { echo "build.sh: $f not found: give the SMCDEL and HasCacBDD source trees" >&2; exit 2; }
done
db="$out/package.db"
[ -d "$db" ] || ghc-pkg init "$db"
# HasCacBDD's own build: Setup.hs runs `make` in cpp/ (CacBDD, -O3) and c/ (the C wrapper), then GHC.
cp -R "$cacbdd" "$out/HasCacBDD"
cd "$out/HasCacBDD"
ghc -O Setup.hs -o Setup
./Setup configure --package-db="$db" --prefix="$out/inst" -O
MAKEFLAGS=-j1 ./Setup build -j1
./Setup install
# SMCDEL's library modules (only those SmcdelBench.hs imports) and the benchmark: -O, as cabal builds them.
mkdir -p "$out/build" "$out/bin"
ghc --make -O -j1 -Wall -package-db "$db" -i"$smcdel/src" -outputdir "$out/build" \
  -L"$out/HasCacBDD/c" -o "$out/bin/smcdel-bench" "$here/SmcdelBench.hs"
"$out/bin/smcdel-bench" muddy 3
