# Shared by the deploy tests (shell: they drive the launcher, systemd, compose and the
# package as an operator would). IGMS_BIN_DIR, IGMS_SOURCE_DIR and IGMS_BUILD_DIR come
# from CTest.
set -euo pipefail
SRC="${IGMS_SOURCE_DIR:?}"
BIN="${IGMS_BIN_DIR:?}"
TEST_NAME="${TEST_NAME:-$(basename "$0" .sh)}"
SCRATCH=$(mktemp -d "${TMPDIR:-/tmp}/igms-${TEST_NAME//\//-}.XXXXXX")
FAILURES=0
CLEANUPS=()
cleanup() {
  local c
  for c in "${CLEANUPS[@]}"; do eval "$c" >/dev/null 2>&1 || true; done
  rm -rf "$SCRATCH"
}
trap cleanup EXIT
at_exit() { CLEANUPS=("$1" "${CLEANUPS[@]}"); }

note() { printf '%s: %s\n' "$TEST_NAME" "$*"; }
fail() {
  printf '%s: FAILED: %s\n' "$TEST_NAME" "$*" >&2
  FAILURES=$((FAILURES + 1))
}
check() {  # check "what" COMMAND...: COMMAND must succeed
  local what="$1"
  shift
  if "$@"; then note "ok: $what"; else fail "$what"; fi
}
finish() {
  if [ "$FAILURES" -ne 0 ]; then
    note "$FAILURES checks failed"
    exit 1
  fi
  note "all checks passed"
}
# Free TCP ports on loopback, N of them (the kernel picks them; they are released at once).
free_ports() {
  python3 -c 'import socket,sys
socks=[socket.socket() for _ in range(int(sys.argv[1]))]
for s in socks: s.bind(("127.0.0.1",0))
print(" ".join(str(s.getsockname()[1]) for s in socks))' "$1"
}
# Waits for a condition (a command) for up to SECONDS; its polling interval is short.
wait_for() {
  local seconds="$1" deadline
  shift
  deadline=$((SECONDS + seconds))
  until "$@"; do
    [ $SECONDS -lt $deadline ] || return 1
    sleep 0.05
  done
}
# Whether a process has ended (a zombie not yet reaped by its parent counts as ended).
gone() {
  local state
  state=$(awk '{ print $3 }' "/proc/$1/stat" 2>/dev/null) || return 0
  [ -z "$state" ] || [ "$state" = Z ] || [ "$state" = X ]
}
