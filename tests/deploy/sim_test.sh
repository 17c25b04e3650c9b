#!/usr/bin/env bash
# igms sim DEVICE --link PATH: each device simulator alone on a pseudo-terminal, with no
# daemon reading it, and the device's own daemon on the other end as the "other software":
# opened as a real serial port (--serial PATH), it receives readings from the simulator.
TEST_NAME=deploy/sim
. "$(dirname "$0")/lib.sh"

DEVICES=(joystick viewer ranger platform voice)
read -r -a PORTS <<<"$(free_ports 10)"
status() {  # status PORT SERVICE: the LinkStatus JSON
  "$BIN/igmsctl" --port "$1" --timeout 1000 call "$2.Status" 2>/dev/null
}
connected() { status "$1" "$2" | grep -q '"state":"CONNECTED"' && status "$1" "$2" | grep -qv '"readings":"0"'; }
# The voice simulator says nothing until spoken to: the operator's input through its SimService.
speak() { "$BIN/igmsctl" --port "$1" --timeout 1000 call SimService.Inject '{"spoken":"freeze"}' >/dev/null 2>&1 || true; }
connected_or_speak() { speak "$1"; connected "$2" VoiceService; }
i=0
for device in "${DEVICES[@]}"; do
  sim_port=${PORTS[$i]}
  daemon_port=${PORTS[$((i + 1))]}
  i=$((i + 2))
  link="$SCRATCH/$device.tty"
  "$BIN/igms" sim "$device" --link "$link" --port "$sim_port" >"$SCRATCH/$device-sim.log" 2>&1 &
  at_exit "kill $!"
  service="$(tr '[:lower:]' '[:upper:]' <<<"${device:0:1}")${device:1}Service"
  check "igms sim $device publishes its pseudo-terminal at --link" wait_for 10 test -e "$link"
  check "igms sim $device: no driver reads it" \
    wait_for 10 bash -c "'$BIN/igmsctl' --port $sim_port --timeout 1000 call $service.Status 2>/dev/null | grep -q 'no driver reads it'"
  "$BIN/igms-${device}d" --serial "$link" --port "$daemon_port" >"$SCRATCH/$device-daemon.log" 2>&1 &
  at_exit "kill $!"
done
connected_or_speak() { speak "$1"; connected "$2" VoiceService; }
i=0
for device in "${DEVICES[@]}"; do
  sim_port=${PORTS[$i]}
  daemon_port=${PORTS[$((i + 1))]}
  i=$((i + 2))
  if [ "$device" = voice ]; then wait_for 10 connected_or_speak "$sim_port" "$daemon_port" || true; fi
  service="$(tr '[:lower:]' '[:upper:]' <<<"${device:0:1}")${device:1}Service"
  if wait_for 15 connected "$daemon_port" "$service"; then
    note "ok: igms-${device}d on the link reads the simulator: $(status "$daemon_port" "$service" | grep -o '"readings":"[0-9]*"')"
  else
    fail "igms-${device}d on the link: $(status "$daemon_port" "$service"); $(tail -2 "$SCRATCH/$device-daemon.log")"
  fi
done
"$BIN/igms" sim platform >/dev/null 2>&1 && rc=0 || rc=$?
check "igms sim without --link: exit 2" test "$rc" = 2
finish
