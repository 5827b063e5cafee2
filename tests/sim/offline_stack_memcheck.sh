#!/usr/bin/env bash
# The offline stack (planner, kinematics applying a calibration, bridge,
# virtual rig, tracker) reads no byte it did not write: Valgrind's memcheck
# on a calibrated run of the example rig, every effect on. A read of an
# uninitialised field (a held setpoint's acceleration, say) makes a
# calibration's result depend on what the stack held before, and so on how
# the program was compiled; ASan does not see it, memcheck does.
# Usage: offline_stack_memcheck.sh EDSP_SIM EDSP_GAP CONFIG
set -euo pipefail
sim=$1 gap=$2 config=$3
work=$(mktemp -d /tmp/edsp_test_memcheck_XXXXXX)
# Removed when memcheck found nothing; kept, and named, for a failure.
trap 'status=$?; if [ $status -eq 0 ]; then rm -rf "$work"; else echo "kept $work for inspection" >&2; fi' EXIT
# A calibration of the example rig, as an operator would make it (natively).
# At the calibration group's speeds: the same motions in less than half the
# simulated time, which memcheck runs some 50× slower than the CPU does.
fast=(--max-speed-m-s 0.25 --max-speed-rad-s 0.5)
"$sim" rig --config "$config" --out "$work/fit" --motions Lz Lx Rz Ry M1 M2 --stops 3 --dwell-s 0.2 \
  --tracker-noise-m 5e-6 --seed 7 "${fast[@]}" >/dev/null
"$gap" diagnose --config "$config" --data "$work/fit/measurement.csv" --save-model "$work/model.json" >/dev/null
# A short calibrated run under memcheck: its blend-in at home, a motion.
# Origins are tracked only to explain a failure (they double the time).
held=("$sim" rig --config "$config" --out "$work/held" --motions Ly --stops 2 --dwell-s 0.2 --tracker-noise-m 5e-6
  --calibration "$work/model.json" --apply-ambiguous "${fast[@]}")
if ! valgrind --error-exitcode=9 -q "${held[@]}" >/dev/null; then
  echo "memcheck found the reads above; again with --track-origins=yes, to say where their bytes came from:" >&2
  valgrind --error-exitcode=9 --track-origins=yes -q "${held[@]}" >/dev/null || true
  exit 9
fi
echo "memcheck: no read of an uninitialised or invalid byte in the calibrated offline stack"
