#!/usr/bin/env bash
# deploy/check_layers passes on the tree, and on a copy of it fails, naming
# the file and line, for an include that points up (kinematics → rig), for
# a library linked up (the diagnosis core → rig), and for a module folder
# the table does not know.
set -euo pipefail
SOURCE=$1
CHECK=$SOURCE/deploy/check_layers
"$CHECK" "$SOURCE"

copy=$(mktemp -d)
trap 'rm -rf "$copy"' EXIT
for dir in "$SOURCE"/*/; do
  name=$(basename "$dir")
  case $name in build*) continue ;; esac
  ln -s "$SOURCE/$name" "$copy/$name"
done
rm "$copy/kinematics" && cp -r "$SOURCE/kinematics" "$copy/kinematics"
victim=$copy/kinematics/src/platform_model.cpp
line=$(($(wc -l <"$victim") + 1))
echo '#include "edsp/rig/virtual_rig.h"' >>"$victim"
if out=$("$CHECK" "$copy" 2>&1); then
  echo "FAIL: an include of rig/ from kinematics/ passed: $out"; exit 1
fi
expected="kinematics/src/platform_model.cpp:$line: kinematics/ includes edsp/rig/virtual_rig.h"
[[ $out == *"$expected"* ]] || { echo "FAIL: expected \"$expected\" in: $out"; exit 1; }
echo "refused as expected: $out"

rm "$copy/diagnosis" && cp -r "$SOURCE/diagnosis" "$copy/diagnosis"
cmake_file=$copy/diagnosis/CMakeLists.txt
line=$(($(wc -l <"$cmake_file") + 1))
echo 'target_link_libraries(edsp_diagnosis PRIVATE edsp::rig)' >>"$cmake_file"
cp "$SOURCE/kinematics/src/platform_model.cpp" "$copy/kinematics/src/platform_model.cpp"
if out=$("$CHECK" "$copy" 2>&1); then
  echo "FAIL: the diagnosis core linking rig/ passed: $out"; exit 1
fi
expected="diagnosis/CMakeLists.txt:$line: diagnosis/ links edsp::rig (of rig/)"
[[ $out == *"$expected"* ]] || { echo "FAIL: expected \"$expected\" in: $out"; exit 1; }
echo "refused as expected: $out"
cp "$SOURCE/diagnosis/CMakeLists.txt" "$cmake_file"

mkdir -p "$copy/newmodule/include/edsp/newmodule"
cp "$SOURCE/kinematics/src/platform_model.cpp" "$copy/kinematics/src/platform_model.cpp"
if out=$("$CHECK" "$copy" 2>&1); then
  echo "FAIL: a module outside the table passed: $out"; exit 1
fi
[[ $out == *"newmodule/ has no line in the layer table"* ]] || { echo "FAIL: unexpected: $out"; exit 1; }
echo "refused as expected: $out"
