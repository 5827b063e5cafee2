#!/usr/bin/env bash
# deploy/check_layers passes on the tree, and on a copy of it fails, naming
# the file and line, for an include that points up (kinematics → rig), for
# a library linked up (the diagnosis core → rig), for an unprefixed include
# of a header not beside the file, for a test including what is no module,
# for a module linking GoogleTest, and for a module folder the table does
# not know.
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

# refused CHECK_OUTPUT_EXPECTED: the check must fail and say EXPECTED.
refused() {
  local out
  if out=$("$CHECK" "$copy" 2>&1); then
    echo "FAIL: passed, expected \"$1\": $out"; exit 1
  fi
  [[ $out == *"$1"* ]] || { echo "FAIL: expected \"$1\" in: $out"; exit 1; }
  echo "refused as expected: $out"
}

victim=$copy/kinematics/src/platform_model.cpp
line=$(($(wc -l <"$victim") + 1))
echo '#include "group_file.h"' >>"$victim"
refused "kinematics/src/platform_model.cpp:$line: kinematics/ includes \"group_file.h\", which is not beside it"
cp "$SOURCE/kinematics/src/platform_model.cpp" "$victim"

rm "$copy/tests" && mkdir -p "$copy/tests" && cp "$SOURCE/tests/CMakeLists.txt" "$copy/tests/"
echo '#include "edsp/nomodule/thing.h"' >"$copy/tests/stray_test.cpp"
refused "tests/stray_test.cpp:1: tests/ includes edsp/nomodule/thing.h, of no module in the layer table"
rm "$copy/tests/stray_test.cpp"

line=$(($(wc -l <"$cmake_file") + 1))
echo 'target_link_libraries(edsp_diagnosis PRIVATE GTest::gtest)' >>"$cmake_file"
refused "diagnosis/CMakeLists.txt:$line: diagnosis/ links a test library (GTest::gtest)"
cp "$SOURCE/diagnosis/CMakeLists.txt" "$cmake_file"

mkdir -p "$copy/newmodule/include/edsp/newmodule"
cp "$SOURCE/kinematics/src/platform_model.cpp" "$copy/kinematics/src/platform_model.cpp"
if out=$("$CHECK" "$copy" 2>&1); then
  echo "FAIL: a module outside the table passed: $out"; exit 1
fi
[[ $out == *"newmodule/ has no line in the layer table"* ]] || { echo "FAIL: unexpected: $out"; exit 1; }
echo "refused as expected: $out"
