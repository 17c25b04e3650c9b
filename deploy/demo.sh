#!/usr/bin/env bash
# The main job (README: deploy/lab demo): the whole lab on this machine, and an operator
# session played by a script through the same paths a person's hands and voice take.
#
#   1. a fresh run folder (inside IGMS_RUN_DIR when set) with a fresh database;
#   2. every server and device daemon of the lab file started (simulated devices and site);
#   3. igms-plan writes the session that models every object of the simulated site;
#   4. igms-control plays it headless: looks, freezes, moves the pointer, marks, ranges and
#      names each object, through the device simulators' serial lines;
#   5. igms-truth-table prints the true-versus-modelled table from the database.
# Everything is stopped at the end, whatever happens. Exit: 0 when every object was
# modelled; otherwise non-zero, naming the step that failed.
#
#   deploy/demo.sh [BUILD_DIR]
# Environment: IGMS_CONFIG (default deploy/lab.yaml), IGMS_RUN_DIR (default .lab-run).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${1:-$ROOT/build}"
CONFIG="${IGMS_CONFIG:-$ROOT/deploy/lab.yaml}"
BASE="${IGMS_RUN_DIR:-$ROOT/.lab-run}"
RUN="$BASE/demo-$(date -u +%Y%m%d-%H%M%S)"
say() { printf 'demo: %s\n' "$*" >&2; }
fail() {
  say "step '$1' failed: $2"
  say "logs, database and results: $RUN"
  exit 1
}

for p in igms igmsctl igms-video-server igms-object-server igms-sound-server igms-viewerd \
  igms-joystickd igms-rangerd igms-voiced igms-platformd igms-control igms-plan igms-truth-table; do
  [ -x "$BUILD/bin/$p" ] || fail "check programs" "$BUILD/bin/$p is not built (deploy/lab build)"
done
mkdir -p "$RUN"
say "run folder: $RUN"

# A lab already answering on these ports would take our calls: refuse rather than mix.
if IGMS_RUN_DIR="$RUN" "$ROOT/deploy/lab" status >/dev/null 2>&1; then
  fail "start the lab" "a lab already answers on the ports of $CONFIG (stop it: deploy/lab down)"
fi
stop_lab() { IGMS_RUN_DIR="$RUN" "$ROOT/deploy/lab" down >/dev/null 2>&1 || true; }
trap stop_lab EXIT
IGMS_RUN_DIR="$RUN" IGMS_CONFIG="$CONFIG" "$ROOT/deploy/lab" up 2>&1 | sed 's/^/  /' >&2

say "planning the session (igms-plan)"
"$BUILD/bin/igms-plan" --config "$CONFIG" --out "$RUN/session.yaml" 2>"$RUN/plan.log" ||
  fail "plan" "$(tail -3 "$RUN/plan.log")"
objects=$(grep -c '^- say:' "$RUN/session.yaml" || true)
say "$objects objects to model; the session's script is $RUN/session.yaml"

say "playing the session (igms-control --script), progress below; full log $RUN/control.log"
set +e
# --wait: the servers may still be starting; the session begins once each one answers.
timeout 900 "$BUILD/bin/igms-control" --config "$CONFIG" --database "$RUN/igms.db" --wait \
  --script "$RUN/session.yaml" >"$RUN/control.log" 2>&1 &
control=$!
tail -n +1 -f "$RUN/control.log" --pid=$control 2>/dev/null |
  grep --line-buffered -E 'session started|say: |stored in|not found|NOT stored|script |critical|error' |
  sed -u -E 's/^[0-9-]+ ([0-9:.]+) \[control\] \[[a-z]+\] /  \1 /' >&2
wait $control
status=$?
set -e
[ $status -eq 0 ] || fail "session" "igms-control exited $status: $(grep -E 'critical|error' "$RUN/control.log" | tail -2)"

say "the table: true against modelled (igms-truth-table)"
set +e
"$BUILD/bin/igms-truth-table" --config "$CONFIG" --database "$RUN/igms.db" \
  --json "$RUN/results.json" --require-all | tee "$RUN/table.txt"
status=${PIPESTATUS[0]}
set -e
[ $status -eq 0 ] || fail "table" "not every object was modelled (see $RUN/table.txt)"
say "done: database $RUN/igms.db, table $RUN/table.txt, logs in $RUN"
