#!/usr/bin/env bash
# No compile of the build tree carries the checkout's or the build tree's
# path in its definitions or flags (a -DX="/path/…"): such an object differs
# from checkout to checkout, and CI's fresh clone would compile it again
# instead of finding it in the compiler cache. Paths reach the code through
# edsp/node/build_paths.h. First, the check must catch such a definition on
# a build file made for it.
set -euo pipefail
BUILD=$1 SOURCE=$2

# Prints each compile whose DEFINES or FLAGS name $2 or $3, from ninja file $1.
offending_compiles() {
  awk -v source="$2" -v build="$3" '
    /^build / { target = $2 }
    /^  (DEFINES|FLAGS) = / && (index($0, source) || index($0, build)) { print target ": " $0 }' "$1"
}

probe=$(mktemp)
trap 'rm -f "$probe"' EXIT
printf 'build x.o: CXX_COMPILER__x_Release /src/x.cpp\n  DEFINES = -DX_DIR=\\"%s\\"\n' "$SOURCE" >"$probe"
[ -n "$(offending_compiles "$probe" "$SOURCE" "$BUILD")" ] ||
  { echo "FAIL: a definition naming $SOURCE went unseen"; exit 1; }

found=$(offending_compiles "$BUILD/build.ninja" "$SOURCE" "$BUILD")
if [ -n "$found" ]; then
  echo "FAIL: compiles that depend on where the checkout is (use edsp/node/build_paths.h):"
  echo "$found" | head -20
  exit 1
fi
echo "no compile names $SOURCE or $BUILD in its definitions or flags"
