#!/usr/bin/env bash
# The main job (README: deploy/lab demo). Runs what the lab has today, and says plainly
# what is not there yet. BUILD is the build folder.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${1:-$ROOT/build}"
export IGMS_RUN_DIR="${IGMS_RUN_DIR:-$ROOT/.lab-run}"
say() { printf 'demo: %s\n' "$*" >&2; }

missing=()
for p in igms-video-server igms-object-server igms-sound-server igms-control; do
  [ -x "$BUILD/bin/$p" ] || missing+=("$p")
done

"$ROOT/deploy/lab" up
trap '"$ROOT/deploy/lab" down' EXIT
sleep 1
"$ROOT/deploy/lab" status || true

if [ -x "$ROOT/deploy/vision-demo.sh" ] && [ -x "$BUILD/bin/igms-video-server" ] && [ -x "$BUILD/bin/igms-object-server" ]; then
  "$ROOT/deploy/vision-demo.sh" "$BUILD"
fi
if [ ${#missing[@]} -gt 0 ]; then
  say "not built yet: ${missing[*]}"
  say "the full session (devices, operator marks, modelling, overlay) needs them"
fi
