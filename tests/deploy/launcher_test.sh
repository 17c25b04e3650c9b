#!/usr/bin/env bash
# deploy/lab up|down|status|logs with real processes on loopback: each is started by
# `igms run`, is up once it answers a ping, the control client is left alone, a pid file
# naming another program is not trusted, --only and --here select, a process that cannot
# start is named, and a lab file with lab.tls: on gets its certificates in its run folder.
TEST_NAME=deploy/launcher
. "$(dirname "$0")/lib.sh"

read -r P1 P2 P3 P4 <<<"$(free_ports 4)"
lab() { IGMS_RUN_DIR="$SCRATCH/run" IGMS_BIN_DIR="$BIN" "$SRC/deploy/lab" "$@"; }
LAB="$SCRATCH/lab.yaml"
# The platform listens on 127.0.0.2 with no bind: a server listens at its host.
cat >"$LAB" <<YAML
lab:
  token: "launcher-test"
  calibration: $SRC/common/calibration/data/thesis_calibration.yaml
processes:
  control:
    program: igms-control
  platform:
    program: igms-platformd
    host: 127.0.0.2
    port: $P1
    serial: simulate
  viewer:
    program: igms-viewerd
    host: 127.0.0.1
    port: $P2
    serial: simulate
  faraway:
    program: igms-viewerd
    host: 192.0.2.1
    port: $P3
    serial: simulate
YAML
at_exit "IGMS_DOWN_TIMEOUT=2 lab down --config '$LAB'"

# igms run and igms config table, the launcher's two tools.
table=$("$BIN/igms" config table --config "$LAB")
check "config table: who runs where" grep -qE "^platform +igms-platformd +127\.0\.0\.2 +$P1\$" <<<"$table"
check "config table: the control client has no host or port" grep -qE '^control +igms-control +- +-$' <<<"$table"
"$BIN/igms" run nosuch --config "$LAB" 2>"$SCRATCH/err" && rc=0 || rc=$?
check "igms run refuses an unknown process (exit 2)" test "$rc" = 2
check "igms run names the processes there are" grep -q 'has no process .nosuch.' "$SCRATCH/err"

# --here: 192.0.2.1 (TEST-NET) is not this machine, so faraway is not started.
check "up --here starts this machine's servers" lab up --here --config "$LAB"
RUN=$(ls -d "$SCRATCH"/run/lab-*)
check "the run folder is the lab file's own" test -f "$RUN/platform.pid" -a -f "$RUN/viewer.pid"
check "the control client is not started" test ! -e "$RUN/control.pid"
check "faraway (another host) is not started" test ! -e "$RUN/faraway.pid"
check "the platform listens at its host, 127.0.0.2" \
  bash -c "ss -Hltn 'sport = :$P1' | grep -q '127.0.0.2:$P1'"
check "status: platform up" bash -c "IGMS_RUN_DIR='$SCRATCH/run' '$SRC/deploy/lab' status --only platform,viewer --config '$LAB' | grep -qE '^platform .*127.0.0.2:$P1 +[0-9]+ +up'"
check "status: the platform's clock offset, within 10 ms on one host however loaded" bash -c "IGMS_RUN_DIR='$SCRATCH/run' '$SRC/deploy/lab' status --only platform --config '$LAB' | grep -qE '^platform .* up +clock [+-][0-9]\.[0-9]{3} ms\$'"
out=$(lab up --here --config "$LAB" 2>&1)
check "up again: already running" grep -q 'platform already running' <<<"$out"
check "logs show each one's log" bash -c "IGMS_RUN_DIR='$SCRATCH/run' IGMS_BIN_DIR='$BIN' '$SRC/deploy/lab' logs viewer --config '$LAB' | grep -q ."

# A pid file whose pid is another program's: not trusted, not signalled.
viewer_pid=$(cut -d' ' -f1 "$RUN/viewer.pid" || echo 0)
sleep 300 &
other=$!
at_exit "kill $other"
echo "$other igms-platformd" >"$RUN/platform.pid.other"
platform_pid=$(cut -d' ' -f1 "$RUN/platform.pid" || echo 0)

# --only: the viewer alone goes down.
check "down --only viewer" lab down --only viewer --config "$LAB"
check "the viewer exited" wait_for 5 gone "$viewer_pid"
check "the platform still runs" kill -0 "$platform_pid"
cp "$RUN/platform.pid" "$SCRATCH/platform.pid.real" || true
mv "$RUN/platform.pid.other" "$RUN/platform.pid"
out=$(lab down --config "$LAB" 2>&1)
check "down does not trust a pid file naming another program" grep -q 'names no running igms-platformd' <<<"$out"
check "... and does not signal that process" kill -0 "$other"
cp "$SCRATCH/platform.pid.real" "$RUN/platform.pid" || true
check "down" lab down --config "$LAB"
check "the platform exited" wait_for 5 gone "$platform_pid"
check "no pid files are left" bash -c "! ls '$RUN'/*.pid 2>/dev/null"
lab status --config "$LAB" --only viewer >/dev/null 2>&1 && rc=0 || rc=$?
check "status after down: not up (exit 1)" test "$rc" = 1

# A process that cannot start is named, and up fails.
BAD="$SCRATCH/bad.yaml"
cat >"$BAD" <<YAML
lab:
  calibration: $SRC/common/calibration/data/thesis_calibration.yaml
processes:
  viewer:
    program: igms-viewerd
    port: $P4
    serial: simulate
    serail: /dev/ttyS0
YAML
out=$(lab up --config "$BAD" 2>&1) && rc=0 || rc=$?
check "up fails when a process cannot start" test "$rc" != 0
check "... and names it" grep -q 'viewer exited while starting' <<<"$out"
check "... with its log's reason" grep -q 'unknown key processes.viewer.serail' <<<"$out"
check "a second lab file has its own run folder" test "$(ls -d "$SCRATCH"/run/* | wc -l)" = 2

# A lab file that says lab.tls: on and names no folder: up makes the authority and the
# certificates in its run folder, the process serves TLS only, status pings with them.
read -r P5 <<<"$(free_ports 1)"
TLS_LAB="$SCRATCH/tls.yaml"
cat >"$TLS_LAB" <<YAML
lab:
  tls: on
  calibration: $SRC/common/calibration/data/thesis_calibration.yaml
processes:
  viewer:
    program: igms-viewerd
    port: $P5
    serial: simulate
YAML
at_exit "IGMS_DOWN_TIMEOUT=2 lab down --config '$TLS_LAB'"
check "up on a TLS lab file" lab up --config "$TLS_LAB"
TLS_RUN=$(ls -d "$SCRATCH"/run/tls-*)
check "its certificates are made in its run folder" test -f "$TLS_RUN/certs/ca.crt" -a -f "$TLS_RUN/certs/viewer.key"
check "the viewer listens with TLS" grep -q 'listening on .*(TLS 1.3, mutual certificates)' "$TLS_RUN/viewer.log"
check "status pings it with those certificates" lab status --config "$TLS_LAB"
check "a plain client is refused" bash -c "! '$BIN/igmsctl' --port $P5 --timeout 1000 ping --pings 0 >/dev/null 2>&1"
check "down on a TLS lab file" lab down --config "$TLS_LAB"
finish
