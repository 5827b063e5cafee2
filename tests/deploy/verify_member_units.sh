#!/bin/sh
# The per-member systemd units edsp-launch writes for each host of a group
# pass systemd's own checker, drop-ins and target included (any output of
# systemd-analyze verify is a failure).
#   verify_member_units.sh EDSP_LAUNCH GROUP_FILE ROOT HOST...
set -eu
launch=$1 group=$2 root=$3
shift 3
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
for host in "$@"; do
  mkdir "$d/$host"
  "$launch" "$group" --host "$host" --write-units "$d/$host" --root "$root" >/dev/null
  units=$(cd "$d/$host" && ls -d edsp@*.service.d | sed 's/\.d$//')
  target=$(cd "$d/$host" && ls edsp-*.target)
  out=$(cd "$d/$host" && SYSTEMD_UNIT_PATH="$d/$host:" systemd-analyze verify --man=no $units "$target" 2>&1) || true
  if [ -n "$out" ]; then
    echo "$host: $out"
    exit 1
  fi
  echo "$host:" $units "$target" verified
done
