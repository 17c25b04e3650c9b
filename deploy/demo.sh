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
# Every connection is TLS with the lab's certificates (docs/security.md), made in the run
# folder: a lab nobody else on the network can join, though it runs on loopback. --plain runs
# it on plain TCP, as does a lab file that says lab.tls: off; a lab file that names its own
# folder (lab.certs) has its certificates made there.
#
#   deploy/demo.sh [--tls | --plain] [--objects NAME[,NAME...]] [BUILD_DIR]
#       --objects: model only these objects of the site (a short run)
# Environment: IGMS_CONFIG (default deploy/lab.yaml), IGMS_RUN_DIR (default .lab-run).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TLS=""
OBJECTS=()
BUILD="$ROOT/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --tls) TLS=on; shift ;;
    --plain) TLS=off; shift ;;
    --objects) [ $# -ge 2 ] || { echo "demo: --objects needs NAMES" >&2; exit 2; }
      IFS=, read -r -a OBJECTS <<<"$2"; shift 2 ;;
    -h|--help) awk 'NR == 1 { next } /^#/ { sub(/^# ?/, ""); print; next } { exit }' "$0"; exit 0 ;;
    -*) echo "demo: unknown option '$1' (try: deploy/demo.sh --help)" >&2; exit 2 ;;
    *) BUILD="$1"; shift ;;
  esac
done
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

# The programs deploy/lab starts are this build's.
export IGMS_CONFIG="$CONFIG" IGMS_BIN_DIR="${IGMS_BIN_DIR:-$BUILD/bin}"
# A lab already answering on these ports would take our calls: refuse rather than mix.
if IGMS_RUN_DIR="$RUN" "$ROOT/deploy/lab" status >/dev/null 2>&1; then
  fail "start the lab" "a lab already answers on the ports of $CONFIG (stop it: deploy/lab down)"
fi

# TLS unless told otherwise (--plain, or the lab file's lab.tls: off). deploy/lab makes the
# authority and every process's certificate (IGMS_TLS, IGMS_CERTS); the clients started here
# are given the same folder.
file_tls=$("$BUILD/bin/igms" config get lab.tls --config "$CONFIG" 2>/dev/null || true)
case "$file_tls" in true) file_tls=on ;; false) file_tls=off ;; esac
[ -n "$TLS" ] || TLS="${file_tls:-on}"
[ "$TLS" = on ] || [ "$file_tls" != on ] ||
  fail "start the lab" "--plain, but $CONFIG says lab.tls: on"
CLIENT_ARGS=()
if [ "$TLS" = on ]; then
  CLIENT_ARGS=(--set lab.tls=on)
  if certs=$("$BUILD/bin/igms" config get lab.certs --config "$CONFIG" 2>/dev/null) && [ -n "$certs" ]; then
    say "TLS 1.3 on every connection; the lab file's certificates (lab.certs: $certs)"
  else
    export IGMS_CERTS="$RUN/certs"
    CLIENT_ARGS+=(--set "lab.certs=$IGMS_CERTS")
    say "TLS 1.3 on every connection; the lab's authority and certificates in $IGMS_CERTS"
  fi
else
  say "plain TCP (no TLS): $([ "$file_tls" = off ] && echo "the lab file says lab.tls: off" || echo --plain)"
fi
export IGMS_TLS="$TLS"

stop_lab() { IGMS_RUN_DIR="$RUN" "$ROOT/deploy/lab" down >/dev/null 2>&1 || true; }
trap stop_lab EXIT
IGMS_RUN_DIR="$RUN" "$ROOT/deploy/lab" up 2>&1 | sed 's/^/  /' >&2 ||
  fail "start the lab" "a process did not answer (above); logs in $RUN"

say "planning the session (igms-plan)"
ONLY=()
[ ${#OBJECTS[@]} -eq 0 ] || ONLY=(--objects "${OBJECTS[@]}")
"$BUILD/bin/igms-plan" --config "$CONFIG" "${CLIENT_ARGS[@]}" "${ONLY[@]}" \
  --out "$RUN/session.yaml" 2>"$RUN/plan.log" ||
  fail "plan" "$(tail -3 "$RUN/plan.log")"
objects=$(grep -c '^- say:' "$RUN/session.yaml" || true)
say "$objects objects to model; the session's script is $RUN/session.yaml"

say "playing the session (igms-control --script), progress below; full log $RUN/control.log"
set +e
# --wait: the servers may still be starting; the session begins once each one answers.
timeout 900 "$BUILD/bin/igms-control" --config "$CONFIG" "${CLIENT_ARGS[@]}" --database "$RUN/igms.db" --wait \
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
"$BUILD/bin/igms-truth-table" --config "$CONFIG" "${CLIENT_ARGS[@]}" "${ONLY[@]}" \
  --database "$RUN/igms.db" --json "$RUN/results.json" --require-all | tee "$RUN/table.txt"
status=${PIPESTATUS[0]}
set -e
[ $status -eq 0 ] || fail "table" "not every object was modelled (see $RUN/table.txt)"
say "done: database $RUN/igms.db, table $RUN/table.txt, logs in $RUN"
