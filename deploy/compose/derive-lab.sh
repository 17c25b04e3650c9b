#!/usr/bin/env bash
# Derives deploy/compose/lab.yaml, the lab file docker-compose mounts into every container,
# from deploy/lab.yaml by cmake/DeriveLabFile.cmake, the generator of the installed lab file:
# only hosts (each process's compose service, named as the process) and paths (the image's
# installed ones) change; each server listens at its host, its container's address on the
# lab network. The test deploy/compose checks the committed file is this script's output.
#
#   deploy/compose/derive-lab.sh [OUTPUT]     (default deploy/compose/lab.yaml)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OUTPUT="${1:-$ROOT/deploy/compose/lab.yaml}"
INPUT="$ROOT/deploy/lab.yaml"

rewrites=(
  # The image installs under the prefix /usr (Dockerfile).
  "lab.calibration=/usr/share/igms/thesis_calibration.yaml"
  # The control client's database, in its container's volume.
  "lab.database=/var/lib/igms/igms-db"
)
# Every serving process (one with a host) is reached at its service's name.
while read -r name; do
  rewrites+=("processes.$name.host=$name")
done < <(awk '/^processes:/ { in_p = 1; next } /^[^ #]/ { in_p = 0 }
  in_p && /^  [A-Za-z0-9_-]+:/ { sub(/:.*/, ""); sub(/^ +/, ""); name = $0 }
  in_p && /^    host:/ { print name }' "$INPUT")

IFS='|'
cmake -DINPUT="$INPUT" -DOUTPUT="$OUTPUT" -DREWRITE="${rewrites[*]}" \
  -DNOTE="The docker-compose lab (docker-compose.yml mounts it read-only as /etc/igms/lab.yaml).
Derived from deploy/lab.yaml by deploy/compose/derive-lab.sh: edit that file, then rerun it.
Only hosts (each process's service) and paths differ." \
  -P "$ROOT/cmake/DeriveLabFile.cmake"
