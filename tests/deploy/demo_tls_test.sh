#!/usr/bin/env bash
# The main job (deploy/demo.sh) on TLS, its default, cut to one object: the lab's authority
# and certificates are made in the run folder, every server of the lab listens with TLS, the
# session's client (igms-control) is served by them, so it spoke TLS too (a plain client is
# refused; shown here on a server started from the same files), and the object is modelled.
# Then the same cut run with --plain: no certificates, no TLS. Free ports, not the lab
# file's (a copy of deploy/lab.yaml with its ports replaced).
TEST_NAME=deploy/demo_tls
. "$(dirname "$0")/lib.sh"

OBJECT=lying_0
read -r -a PORTS <<<"$(free_ports 9)"
LAB="$SCRATCH/lab.yaml"
awk -v ports="${PORTS[*]}" -v src="$SRC" -v db="$SCRATCH/igms-db" '
  BEGIN { n = split(ports, p, " "); i = 0 }
  /^    port: / { sub(/port: .*/, "port: " p[++i]) }
  /^  calibration: \.\.\// { sub(/\.\.\//, src "/") }
  /^  database: / { sub(/database: .*/, "database: " db) }
  /^    output: default/ { sub(/output: default/, "output: \"null\"") }
  { print }' "$SRC/deploy/lab.yaml" >"$LAB"
check "the lab file copy checks" bash -c "'$BIN/igms' config check --config '$LAB' >/dev/null"
demo() {
  IGMS_CONFIG="$LAB" IGMS_RUN_DIR="$SCRATCH/$1" IGMS_BIN_DIR="$BIN" IGMS_DOWN_TIMEOUT=3 \
    "$SRC/deploy/demo.sh" "${@:2}" --objects "$OBJECT" "${IGMS_BUILD_DIR:?}" >"$SCRATCH/$1.out" 2>&1
}
servers=(video object sound viewer joystick ranger voice platform)

# TLS, the default.
start=$SECONDS
if demo tls; then note "ok: the demo on TLS modelled $OBJECT ($((SECONDS - start)) s)"; else
  fail "the demo on TLS: $(grep 'demo: ' "$SCRATCH/tls.out" | tail -3)"
fi
RUN=$(ls -d "$SCRATCH"/tls/demo-* | head -1)
LABRUN=$(ls -d "$RUN"/lab-* | head -1)
check "the demo says its connections are TLS" grep -q 'demo: TLS 1.3 on every connection' "$SCRATCH/tls.out"
check "the lab's authority and certificates are in the run folder" \
  test -f "$RUN/certs/ca.crt" -a -f "$RUN/certs/control.crt" -a -f "$RUN/certs/video.key"
for name in "${servers[@]}"; do
  check "$name listened with TLS" grep -q 'listening on .*(TLS 1.3, mutual certificates)' "$LABRUN/$name.log"
done
check "no server refused a connection" bash -c "! grep -qiE 'refus|requires TLS' '$LABRUN'/*.log"
check "the table has the object modelled" grep -q '^1 objects, 1 modelled' "$RUN/table.txt"

# A server as the demo starts it, from its files: a plain client is refused, one with the
# run folder's certificate is served.
read -r port <<<"$(free_ports 1)"
"$BIN/igms" run platform --config "$LAB" -- --set lab.tls=on --set "lab.certs=$RUN/certs" \
  --port "$port" >"$SCRATCH/platform.log" 2>&1 &
at_exit "kill $!"
tls_ping() { "$BIN/igmsctl" --port "$port" --timeout 500 --certs "$RUN/certs" ping --pings 0 >/dev/null 2>&1; }
check "the platform daemon is up on TLS, served with the run folder's certificates" wait_for 10 tls_ping
"$BIN/igmsctl" --port "$port" --timeout 1000 ping --pings 0 >"$SCRATCH/plain-client" 2>&1 && rc=0 || rc=$?
check "a plain client is refused (exit $rc)" test "$rc" != 0
check "... told the server requires TLS" grep -q "requires TLS" "$SCRATCH/plain-client"

# --plain: no certificates, no TLS, the same object modelled.
start=$SECONDS
if demo plain --plain; then note "ok: the demo on plain TCP modelled $OBJECT ($((SECONDS - start)) s)"; else
  fail "the demo with --plain: $(grep 'demo: ' "$SCRATCH/plain.out" | tail -3)"
fi
RUN=$(ls -d "$SCRATCH"/plain/demo-* | head -1)
LABRUN=$(ls -d "$RUN"/lab-* | head -1)
check "--plain says so" grep -q 'demo: plain TCP' "$SCRATCH/plain.out"
check "--plain makes no certificates" test ! -e "$RUN/certs"
check "--plain: the video server listened without TLS" \
  bash -c "grep 'listening on' '$LABRUN/video.log' | grep -vq TLS"
check "--plain: the table has the object modelled" grep -q '^1 objects, 1 modelled' "$RUN/table.txt"
finish
