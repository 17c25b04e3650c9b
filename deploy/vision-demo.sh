#!/usr/bin/env bash
# The vision half of the main job: a video server rendering the simulated site and an object
# server, started here as separate processes on free loopback ports with the lab
# configuration's other values (deploy/lab.yaml), then igms-vision-demo: grab, the four
# operator marks for every object from the ground truth, each Locate over TCP, the table of
# true against modelled pose and size. Results land in RUN_DIR/vision-demo-DATE.
#
#   deploy/vision-demo.sh [BUILD_DIR]
#
# Environment: IGMS_CONFIG (default deploy/lab.yaml), IGMS_RUN_DIR (default .lab-run).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${1:-$ROOT/build}"
CONFIG="${IGMS_CONFIG:-$ROOT/deploy/lab.yaml}"
RUN_DIR="${IGMS_RUN_DIR:-$ROOT/.lab-run}"
OUT="$RUN_DIR/vision-demo-$(date -u +%Y%m%d-%H%M%S)"
say() { printf 'vision-demo: %s\n' "$*" >&2; }

for p in igms-video-server igms-object-server igms-vision-demo; do
  [ -x "$BUILD/bin/$p" ] || { say "$BUILD/bin/$p is not built"; exit 2; }
done
mkdir -p "$OUT"
pids=()
cleanup() {
  local pid
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
}
trap cleanup EXIT

# Starts PROGRAM NAME [ARGS...] on a free port; sets PORT once it listens. Not in a command
# substitution: its subshell's pids would never reach cleanup, and the servers would outlive
# the script.
start() {
  local program="$1" name="$2"
  shift 2
  "$BUILD/bin/$program" --config "$CONFIG" --name "$name" --port 0 \
    --port-file "$OUT/$name.port" "$@" >"$OUT/$name.log" 2>&1 &
  pids+=($!)
  local i
  for i in $(seq 1 200); do
    if [ -s "$OUT/$name.port" ]; then
      PORT=$(cat "$OUT/$name.port")
      return 0
    fi
    kill -0 "${pids[-1]}" 2>/dev/null || break
    sleep 0.1
  done
  say "step 'start $name' failed: $program did not listen; its log:"
  tail -20 "$OUT/$name.log" >&2
  return 1
}

start igms-video-server video --set processes.video.backend=sim || exit 1
VIDEO_PORT=$PORT
say "video server (sim site) on port $VIDEO_PORT, log $OUT/video.log"
start igms-object-server object --set "processes.video.port=$VIDEO_PORT" || exit 1
OBJECT_PORT=$PORT
say "object server on port $OBJECT_PORT, log $OUT/object.log"

"$BUILD/bin/igms-vision-demo" --config "$CONFIG" \
  --set processes.video.backend=sim \
  --set "processes.video.port=$VIDEO_PORT" --set "processes.object.port=$OBJECT_PORT" \
  --out "$OUT"
