#!/usr/bin/env bash
# The lab over several workstations: four network namespaces as hosts (control; video and
# object; sound; the device daemons) on 10.200.0.0/16, joined by veth pairs to a bridge in a
# fifth namespace, so the host's own network is untouched. Each "workstation" runs
# `deploy/lab up --here` from one lab file with a token; the servers listen at their hosts
# (no bind); from the control namespace every server answers a ping, and igms-vision-demo
# grabs from the video host and locates every object through the object server, which
# fetches its frames from the video host's address; the video server follows the platform
# on the daemons' host; a stream's latency from the control host is taken on the clock offset
# estimated from pings. Cleans up whatever happens, stale namespaces of earlier runs too.
# Needs root (ip netns); skips without it, and fails instead when CI=true.
TEST_NAME=deploy/multi_host
. "$(dirname "$0")/lib.sh"

if [ "$(id -u)" -ne 0 ] || ! command -v ip >/dev/null; then
  if [ "${CI:-}" = true ]; then
    fail "needs root and iproute2 for network namespaces (CI=true: not skipped)"
    finish
  fi
  note "SKIPPED: needs root and iproute2 to make network namespaces (ip netns)"
  exit 0
fi

PREFIX=igmsmh
RUNID="$PREFIX-$$"
# Stale namespaces of earlier runs whose test process is gone.
for ns in $(ip netns list | awk '{ print $1 }' | grep "^$PREFIX-" || true); do
  pid=$(cut -d- -f2 <<<"$ns")
  kill -0 "$pid" 2>/dev/null || { ip netns pids "$ns" | xargs -r kill -KILL; ip netns del "$ns"; }
done

# Root is not always enough: a container may forbid namespaces. Then say so and skip, as
# without root; IGMS_REQUIRE_NETNS=1 makes it a failure (a machine that must run it).
if ! probe=$(ip netns add "$RUNID-probe" 2>&1); then
  if [ "${IGMS_REQUIRE_NETNS:-}" = 1 ]; then
    fail "cannot make a network namespace: $probe"
    finish
  fi
  note "SKIPPED: this machine does not allow network namespaces: $probe"
  exit 0
fi
ip netns del "$RUNID-probe"

NAMESPACES=()
remove_namespaces() {
  local ns
  for ns in "${NAMESPACES[@]}"; do
    ip netns pids "$ns" 2>/dev/null | xargs -r kill -KILL 2>/dev/null || true
    ip netns del "$ns" 2>/dev/null || true
  done
}
at_exit remove_namespaces

BRIDGE="$RUNID-br"
ip netns add "$BRIDGE"
NAMESPACES+=("$BRIDGE")
ip -n "$BRIDGE" link add br0 type bridge
ip -n "$BRIDGE" link set br0 up
declare -A ADDRESS=([ctl]=10.200.0.1 [vid]=10.200.0.2 [snd]=10.200.0.3 [dev]=10.200.0.4)
i=0
for ws in ctl vid snd dev; do
  ns="$RUNID-$ws"
  ip netns add "$ns"
  NAMESPACES+=("$ns")
  ip -n "$BRIDGE" link add "p$i" type veth peer name eth0 netns "$ns"
  ip -n "$BRIDGE" link set "p$i" master br0 up
  ip -n "$ns" addr add "${ADDRESS[$ws]}/16" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" link set lo up
  i=$((i + 1))
done
in_ns() { local ws="$1"; shift; ip netns exec "$RUNID-$ws" "$@"; }
check "the namespaces have no default route" bash -c "! ip -n '$RUNID-ctl' route | grep -q default"

# One lab file for the four: deploy/lab.yaml's processes with hosts on the workstations.
LAB="$SCRATCH/lab.yaml"
sed -e 's/token: ""/token: "multi-host-test"/' \
  -e "s|calibration: ../common|calibration: $SRC/common|" \
  -e "s|database: ../.lab-run/igms-db|database: $SCRATCH/igms-db|" "$SRC/deploy/lab.yaml" |
  awk -v vid=10.200.0.2 -v snd=10.200.0.3 -v dev=10.200.0.4 '
    /^  [a-z]+:/ { name = $1; sub(":", "", name) }
    /^    host: / { h = dev; if (name == "video" || name == "object") h = vid; if (name == "sound") h = snd
                    sub(/host: .*/, "host: " h) }
    /^    output: default/ { sub(/output: default/, "output: \"null\"") }
    { print }' >"$LAB"
if ! "$BIN/igms" config check --config "$LAB" >"$SCRATCH/check" 2>&1; then
  fail "igms config check on the lab file: $(grep -v ': OK$' "$SCRATCH/check")"
fi
RUNDIR="$SCRATCH/run"
lab() { IGMS_RUN_DIR="$RUNDIR" IGMS_BIN_DIR="$BIN" IGMS_DOWN_TIMEOUT=3 "$SRC/deploy/lab" "$@" --config "$LAB"; }
for ws in dev snd vid; do
  at_exit "in_ns $ws env IGMS_RUN_DIR='$RUNDIR' IGMS_BIN_DIR='$BIN' IGMS_DOWN_TIMEOUT=3 '$SRC/deploy/lab' down --here --config '$LAB'"
done
start=$SECONDS
# The daemons first: the video server follows the platform.
for ws in dev snd vid; do
  check "up --here on the $ws host" in_ns "$ws" env IGMS_RUN_DIR="$RUNDIR" IGMS_BIN_DIR="$BIN" \
    "$SRC/deploy/lab" up --here --config "$LAB"
done
note "the lab was up in $((SECONDS - start)) s"
RUN=$(ls -d "$RUNDIR"/lab-*)
check "the control client was not started" test ! -e "$RUN/control.pid"
ping_from_control() { in_ns ctl "$BIN/igmsctl" --config "$LAB" --to "$1" --timeout 2000 ping >/dev/null; }
for name in video object sound viewer joystick ranger voice platform; do
  check "$name answers from the control host" ping_from_control "$name"
done
check "the sound server listens only at the sound host's address" \
  bash -c "in_ns() { ip netns exec '$RUNID-'\$1 \"\${@:2}\"; }; in_ns snd ss -Hltn 'sport = :7303' | grep -q '10.200.0.3:7303'"
check "without the token a server refuses" \
  bash -c "! ip netns exec '$RUNID-ctl' '$BIN/igmsctl' --host 10.200.0.2 --port 7301 --timeout 2000 ping >/dev/null 2>&1"

# The video server follows the platform on the daemons' host.
check "the video server follows the platform at 10.200.0.4" \
  wait_for 10 grep -q "following the platform daemon 'platform' at 10.200.0.4:7315" "$RUN/video.log"
check "the object server fetches its frames from the video host" \
  grep -q 'frames from video at 10.200.0.2:7301' "$RUN/object.log"

# A client on the control host: grab on the video host, locate every object.
start=$SECONDS
if in_ns ctl "$BIN/igms-vision-demo" --config "$LAB" --out "$SCRATCH/vision" >"$SCRATCH/vision.log" 2>&1; then
  note "ok: igms-vision-demo from the control host located every object ($((SECONDS - start)) s)"
else
  fail "igms-vision-demo from the control host: $(tail -3 "$SCRATCH/vision.log")"
fi
located=$(grep -c 'locate .* on frame' "$RUN/object.log" || true)
# The video server's status names the video host and counts the edge jobs it ran.
status=$(in_ns ctl "$BIN/igmsctl" --config "$LAB" --to video --timeout 2000 call VideoService.GetStatus 2>&1 || true)
check "the video server's status names the video host's address" \
  grep -q '"listen_address":"10.200.0.2:7301"' <<<"$status"
done_jobs=$(sed -n 's/.*"edge_jobs_done":"\([0-9]*\)".*/\1/p' <<<"$status")
check "the video host ran the edge jobs (${done_jobs:-none} done)" test "${done_jobs:-0}" -gt 0
# Clocks: the namespaces share one kernel clock, so each offset is within its round trip.
note "$(in_ns ctl "$BIN/igmsctl" --config "$LAB" --to platform --timeout 2000 ping 2>&1 >/dev/null | grep 'clock offset')"
# Latency across hosts: the platform stream's send stamps (the daemons' host) put on the
# control host's clock with the offset estimated from pings first, not compared raw.
stream=$(in_ns ctl "$BIN/igmsctl" --config "$LAB" --to platform --timeout 2000 \
  subscribe PlatformService.Live --count 20 --quiet 2>&1 >/dev/null || true)
note "$(grep 'messages' <<<"$stream")"
check "the platform stream's latency from the control host uses the clock offset from pings" \
  grep -qE "latency p50 .*; the server's clock [+-][0-9.]+ ms \(within .*best of 5 pings\) from this host's" <<<"$stream"
check "the object server located objects on fetched frames ($located)" test "$located" -gt 0
finish
