#!/usr/bin/env bash
# What an installed edsp holds and what runs from it (test deploy.install):
#  1. cmake --install of the build tree into a scratch prefix puts every
#     program (and no benchmark or test), the headers (hand-written and
#     lcm-gen's), the libraries, the CMake package, the jar, the group
#     files, the configs, the docs, the Python package and the systemd
#     units in place; the units name this prefix's programs and group files
#     and pass systemd-analyze verify;
#  2. a project outside the tree (tests/install/consumer) finds it with
#     find_package(edsp), links edsp::kinematics and runs IK and FK on the
#     installed config; the installed Python package computes the same legs;
#  3. cpack -G DEB makes one package; unpacked with dpkg -x, its programs
#     answer --help, edsp-sim computes what the build tree's does on the
#     package's config, its units name /usr, the consumer builds and runs
#     against it, its Python package computes the legs.
# Each missing piece is named. Scratch under /tmp, removed on success, kept
# (named on stderr) on failure.
#   install_test.sh BUILD_DIR CMAKE CPACK GENERATOR MAKE_PROGRAM CXX JAVA(ON|OFF) [PYTHON]
set -euo pipefail
shopt -s nullglob

[ $# -ge 7 ] || { sed -n '2,/^set -euo/p' "$0" | sed '$d' >&2; exit 2; }
build=$1 cmake=$2 cpack=$3 generator=$4 make_program=$5 cxx=$6 java=$7 python=${8:-}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

scratch=$(mktemp -d /tmp/edsp_install_test_XXXXXX)
finish() {
  local rc=$?
  if [ $rc -eq 0 ]; then rm -rf "$scratch"; else echo "install_test: scratch kept in $scratch" >&2; fi
}
trap finish EXIT

fail() { echo "install_test: FAIL: $*" >&2; exit 1; }
step() { echo "== $*"; }
# Runs a command with its output to LOG; on failure shows the log's end.
logged() {
  local log=$1 what=$2
  shift 2
  "$@" >"$log" 2>&1 || { tail -n 40 "$log" >&2; fail "$what (log: $log)"; }
}
# Names every path of $@ (relative to ROOT) that does not exist.
expect_files() {
  local root=$1 what=$2 missing=()
  shift 2
  for f in "$@"; do [ -e "$root/$f" ] || missing+=("$f"); done
  [ ${#missing[@]} -eq 0 ] || fail "$what: missing under $root: ${missing[*]}"
}
# The one file under ROOT named NAME (its folder differs with GNUInstallDirs' LIBDIR).
find_one() {
  local found
  found=$(find "$1" -name "$2" -print -quit)
  [ -n "$found" ] || fail "$3: no $2 under $1"
  echo "$found"
}
# Every build/bin/edsp-* program but the benchmarks (not installed).
programs=()
for f in "$build"/bin/edsp-*; do
  case ${f##*/} in edsp-bench-*) ;; *) programs+=("${f##*/}") ;; esac
done
[ ${#programs[@]} -gt 0 ] || fail "no edsp-* program in $build/bin: build first"

# The checks both installs share: the files, and the units against their prefix.
check_tree() {
  local root=$1 prefix=$2 what=$3
  local files=(share/edsp/groups/sim.toml share/edsp/groups/multihost.toml share/edsp/config/huang2021.toml
    include/edsp/kinematics/platform_model.h include/edsp/planner/motion_client.h include/edsp/channels.h
    include/edsp/pose_setpoint_t.hpp lib/systemd/system/edsp-group@.service lib/systemd/system/edsp@.service
    share/doc/edsp/install.md)
  for p in "${programs[@]}"; do files+=("bin/$p"); done
  [ "$java" = ON ] && files+=(share/java/edsp_lcmtypes.jar)
  [ -n "$python" ] && files+=(lib/python3/dist-packages/edsp/__init__.py)
  expect_files "$root$prefix" "$what" "${files[@]}"
  local extra=("$root$prefix"/bin/edsp-bench-* "$root$prefix"/bin/*_tests)
  [ ${#extra[@]} -eq 0 ] || fail "$what: benchmarks or tests installed: ${extra[*]##*/}"
}
check_units() {
  local root=$1 prefix=$2 what=$3 unit
  for unit in edsp-group@.service edsp@.service; do
    local file=$root$prefix/lib/systemd/system/$unit
    ! grep -n '/opt/edsp\|build/bin\|deploy/groups' "$file" || fail "$what: $unit still points into a checkout"
    [ -z "$root" ] || ! grep -n "$scratch" "$file" || fail "$what: $unit names cpack's staging folder"
  done
  local group=$root$prefix/lib/systemd/system/edsp-group@.service
  grep -q "ExecStart=.* $prefix/bin/edsp-launch " "$group" || fail "$what: edsp-group@.service runs no $prefix/bin/edsp-launch"
  grep -q "EDSP_ROOT=$prefix/share/edsp " "$group" || fail "$what: edsp-group@.service's EDSP_ROOT is not $prefix/share/edsp"
  # shellcheck disable=SC2016  # systemd's variable, literally
  grep -qF '${EDSP_ROOT}/groups/%i.toml' "$group" || fail "$what: edsp-group@.service takes no group file from \${EDSP_ROOT}/groups"
  grep -q "EDSP_BIN_DIR=$prefix/bin" "$root$prefix/lib/systemd/system/edsp@.service" ||
    fail "$what: edsp@.service's EDSP_BIN_DIR is not $prefix/bin"
}
# The units as systemd reads them, for an instance each (any output is a
# failure).
verify_units() {
  local root=$1 what=$2 out unit instance
  command -v systemd-analyze >/dev/null || { echo "(no systemd-analyze: units not verified)"; return 0; }
  mkdir -p "$scratch/verify"
  for unit in edsp-group@.service edsp@.service; do
    case $unit in edsp-group@*) instance=edsp-group@sim.service ;; *) instance=edsp@sim.rig.service ;; esac
    cp "$root/lib/systemd/system/$unit" "$scratch/verify/$instance"
    out=$(systemd-analyze verify --man=no "$scratch/verify/$instance" 2>&1) || true
    [ -z "$out" ] || fail "$what: systemd-analyze verify $instance: $out"
  done
}
# Configures, builds and runs the consumer against PREFIX.
consumer() {
  local prefix=$1 dir=$2 what=$3
  logged "$dir.configure.log" "$what: the consumer does not configure against $prefix" \
    "$cmake" -S "$here/consumer" -B "$dir" -G "$generator" -DCMAKE_MAKE_PROGRAM="$make_program" \
    -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix"
  local found
  found=$(sed -n 's/^edsp_DIR:PATH=//p' "$dir/CMakeCache.txt")
  case $found in "$prefix"/*) ;; *) fail "$what: find_package(edsp) found $found, not the copy under $prefix" ;; esac
  logged "$dir.build.log" "$what: the consumer does not build against $prefix" "$cmake" --build "$dir"
  logged "$dir.run.log" "$what: the consumer failed on $prefix/share/edsp/config/huang2021.toml" \
    "$dir/edsp_consumer" "$prefix/share/edsp/config/huang2021.toml"
  echo "consumer: $(tail -n 1 "$dir.run.log") (edsp_DIR $found)"
}
# The installed Python package: imported from PREFIX, IK at home.
python_package() {
  local prefix=$1 what=$2
  [ -n "$python" ] || return 0
  PYTHONPATH=$prefix/lib/python3/dist-packages "$python" - "$prefix" >"$scratch/python.log" 2>&1 <<'EOF' ||
import sys
import edsp
prefix = sys.argv[1]
assert edsp.__file__.startswith(prefix), f"edsp imported from {edsp.__file__}, not {prefix}"
k = edsp.Kinematics(prefix + "/share/edsp/config/huang2021.toml")
legs = k.ik([k.home])[0]
assert all(abs(l - 1.906353) < 1e-6 for l in legs), f"home legs {legs}"
print("python: home legs", " ".join(f"{l:.6f}" for l in legs))
EOF
    { cat "$scratch/python.log" >&2; fail "$what: the Python package under $prefix"; }
  cat "$scratch/python.log"
}

step "cmake --install $build --prefix <scratch>/prefix"
prefix=$scratch/prefix
logged "$scratch/install.log" "cmake --install failed" "$cmake" --install "$build" --prefix "$prefix"
check_tree "" "$prefix" "cmake --install"
config_file=$(find_one "$prefix" edspConfig.cmake "cmake --install")
expect_files "$(dirname "$config_file")" "cmake --install" edspConfigVersion.cmake edspTargets.cmake
find_one "$prefix" libedsp_kinematics.a "cmake --install" >/dev/null
check_units "" "$prefix" "cmake --install"
verify_units "$prefix" "cmake --install"
echo "installed: ${#programs[@]} programs, $(find "$prefix" -type f | wc -l) files"

step "the consumer against the install"
consumer "$prefix" "$scratch/consumer" "install"
python_package "$prefix" "install"

step "cpack -G DEB, dpkg -x"
logged "$scratch/cpack.log" "cpack failed" "$cpack" --config "$build/CPackConfig.cmake" -G DEB -B "$scratch/deb"
debs=("$scratch"/deb/*.deb)
[ ${#debs[@]} -eq 1 ] || fail "cpack made ${#debs[@]} .deb files in $scratch/deb, not one"
deb=${debs[0]}
[ "$(dpkg-deb -f "$deb" Package)" = edsp ] || fail "$deb: package name is not edsp"
depends=$(dpkg-deb -f "$deb" Depends)
case $depends in *liblcm1*) ;; *) fail "$deb: Depends names no liblcm1: $depends" ;; esac
echo "$(basename "$deb"): $(du -h "$deb" | cut -f1), Depends: $depends"
root=$scratch/root
dpkg -x "$deb" "$root" || fail "dpkg -x $deb"
check_tree "$root" /usr ".deb"
check_units "$root" /usr ".deb"

step "programs from the unpacked package"
for p in "${programs[@]}"; do
  "$root/usr/bin/$p" --help >/dev/null 2>"$scratch/help.err" || fail ".deb: $p --help: $(cat "$scratch/help.err")"
done
echo "${#programs[@]} programs answer --help"
pose=--pose=0.1,-0.05,1.6,0.05,-0.03,0.2
"$root/usr/bin/edsp-sim" pr --config "$root/usr/share/edsp/config/huang2021.toml" "$pose" --json >"$scratch/pr.deb.json" ||
  fail ".deb: edsp-sim pr on the package's config"
"$build/bin/edsp-sim" pr --config "$here/../../config/huang2021.toml" "$pose" --json >"$scratch/pr.build.json"
cmp -s "$scratch/pr.deb.json" "$scratch/pr.build.json" ||
  fail ".deb: edsp-sim pr $pose differs from the build tree's: $(diff "$scratch/pr.deb.json" "$scratch/pr.build.json" | head)"
home=$("$root/usr/bin/edsp-sim" pr --config "$root/usr/share/edsp/config/huang2021.toml" --pose=0,0,1.511,0,0,0 --json |
  sed -n '/"length_m"/,/]/p' | grep -c '^ *1\.906353' || true)
[ "$home" -eq 6 ] || fail ".deb: edsp-sim pr at home gives $home of 6 legs at 1.906353 m"
echo "edsp-sim pr: six legs 1.906353 m at home; $pose as the build tree's"

step "the package's CMake package and Python package"
consumer "$root/usr" "$scratch/consumer-deb" ".deb"
python_package "$root/usr" ".deb"
echo "install_test: ok"
