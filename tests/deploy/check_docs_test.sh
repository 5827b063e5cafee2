#!/usr/bin/env bash
# deploy/check_docs passes on the tree, and on a small checkout fails,
# naming the file and line, for a README table row too long and for a date
# in a doc or in code (a notebook under docs/ too); a date in
# docs/figures.md passes.
set -euo pipefail
SOURCE=$1
CHECK=$SOURCE/deploy/check_docs
"$CHECK" "$SOURCE"

day() { printf '%s-%s-%s' "$1" "$2" "$3"; }  # spelled apart: this file is checked too
copy=$(mktemp -d)
trap 'rm -rf "$copy"' EXIT
mkdir -p "$copy/docs" "$copy/planner/src"
printf '# a project\n\n| folder | what |\n| --- | --- |\n| `a/` | short |\n' >"$copy/README.md"
echo "Measured $(day 2026 11 22) on this machine." >"$copy/docs/figures.md"
echo "// what the code does" >"$copy/planner/src/planner.cpp"
git -C "$copy" init -q && git -C "$copy" add -A
"$CHECK" "$copy" || { echo "FAIL: a clean checkout was refused"; exit 1; }

expect_refused() {  # what it must say
  git -C "$copy" add -A
  if out=$("$CHECK" "$copy" 2>&1); then
    echo "FAIL: passed, expected \"$1\""; exit 1
  fi
  [[ $out == *"$1"* ]] || { echo "FAIL: expected \"$1\" in: $out"; exit 1; }
  echo "refused as expected: $out"
}
printf '| `b/` | %s |\n' "$(printf 'long %.0s' {1..80})" >>"$copy/README.md"
expect_refused "README.md:6: a table row of 411 characters"
sed -i '$d' "$copy/README.md"
echo "// changed on $(day 2026 12 01) after a stall" >>"$copy/planner/src/planner.cpp"
expect_refused "planner/src/planner.cpp:2:// changed on $(day 2026 12 01)"
sed -i '$d' "$copy/planner/src/planner.cpp"
mkdir -p "$copy/docs/notes"
echo "A notebook of $(day 2026 11 23)." >"$copy/docs/notes/history.md"
expect_refused "docs/notes/history.md:1:A notebook of $(day 2026 11 23)"
