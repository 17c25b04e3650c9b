#!/usr/bin/env bash
# Builds the Debian package with CPack and checks it: lintian reports no error, it holds the
# programs, the units, the lab file (a conffile), the calibration, the sound bank and the
# docs, and, unpacked into a scratch root (dpkg-deb -x), its own `igms config check` passes
# on the lab file it installs (paths pointed into that root).
#
#   deploy/check-package.sh [BUILD_DIR] [--no-lintian]
# Prints the package's path last. Exit 0 when every check passes.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$ROOT/build"
LINTIAN=1
for arg in "$@"; do
  case "$arg" in
    --no-lintian) LINTIAN=0 ;;
    -*) echo "check-package: unknown option '$arg'" >&2; exit 2 ;;
    *) BUILD="$arg" ;;
  esac
done
BUILD="$(cd "$BUILD" && pwd)"
say() { printf 'check-package: %s\n' "$*" >&2; }
failures=0
bad() { say "FAILED: $*"; failures=$((failures + 1)); }

OUT="$BUILD/package"
mkdir -p "$OUT"
rm -f "$OUT"/igms_*.deb
start=$SECONDS
(cd "$BUILD" && cpack -G DEB -B "$OUT" >"$OUT/cpack.log" 2>&1) ||
  { tail -20 "$OUT/cpack.log" >&2; say "cpack failed (log $OUT/cpack.log)"; exit 1; }
DEB=$(ls "$OUT"/igms_*.deb)
say "built $(basename "$DEB") ($(du -h "$DEB" | cut -f1)) in $((SECONDS - start)) s"

if [ "$LINTIAN" = 1 ]; then
  if command -v lintian >/dev/null; then
    start=$SECONDS
    lintian --fail-on error "$DEB" >"$OUT/lintian.log" 2>&1 || true
    errors=$(grep -c '^E: ' "$OUT/lintian.log" || true)
    warnings=$(grep -c '^W: ' "$OUT/lintian.log" || true)
    say "lintian: $errors errors, $warnings warnings in $((SECONDS - start)) s (all in $OUT/lintian.log)"
    [ "$errors" = 0 ] || { grep '^E: ' "$OUT/lintian.log" >&2; bad "lintian reports errors"; }
  else
    say "no lintian: not checked (deploy/install-deps.sh installs it)"
  fi
fi

# What the package holds.
contents=$(dpkg-deb -c "$DEB" | awk '{ print $NF }' | sed 's|^\./|/|')
for path in /usr/bin/igms /usr/bin/igms-run /usr/bin/igms-video-server /usr/bin/igms-control \
  /etc/igms/lab.yaml /usr/lib/systemd/system/igms@.service /usr/lib/systemd/system/igms.target \
  /usr/lib/systemd/system/igms@video.service.d/devices.conf \
  /usr/lib/sysusers.d/igms.conf \
  /usr/share/igms/thesis_calibration.yaml /usr/share/doc/igms/copyright /usr/share/doc/igms/deploy.md; do
  grep -qxF "$path" <<<"$contents" || bad "the package has no $path"
done
grep -q '^/usr/share/igms/sounds/.' <<<"$contents" || bad "the package has no sound bank"
dpkg-deb --fsys-tarfile "$DEB" | tar -xO ./usr/share/doc/igms/copyright 2>/dev/null |
  grep -qx 'License: Expat' || bad "the copyright file does not grant the Expat (MIT) licence"
dpkg-deb -I "$DEB" conffiles 2>/dev/null | grep -qxF /etc/igms/lab.yaml ||
  bad "/etc/igms/lab.yaml is not a conffile"

# Unpacked into a scratch root, its own programs check its own lab file.
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
dpkg-deb -x "$DEB" "$TMP"
unit="$TMP/usr/lib/systemd/system/igms@.service"
grep -qxF 'ExecStart=/usr/bin/igms run %i' "$unit" || bad "the unit does not run /usr/bin/igms run %i"
grep -qxF 'Environment=IGMS_CONFIG=/etc/igms/lab.yaml' "$unit" || bad "the unit does not name /etc/igms/lab.yaml"
# The installed file names /usr/share/...: the same files inside the scratch root.
sed -E "s#^(  [a-z_]+: )/usr/#\\1$TMP/usr/#" "$TMP/etc/igms/lab.yaml" >"$TMP/etc/igms/lab.unpacked.yaml"
if check=$("$TMP/usr/bin/igms" config check --config "$TMP/etc/igms/lab.unpacked.yaml" 2>&1); then
  say "igms config check on the unpacked lab file: every process OK"
else
  printf '%s\n' "$check" >&2
  bad "igms config check on the unpacked package's lab file"
fi

# The maintainer scripts, run as dpkg would into the scratch root (DPKG_ROOT): postinst makes
# the sysusers.d group there with systemd-sysusers, and without systemd-sysusers (a
# container) it still succeeds; neither script fails where no systemd runs.
mkdir -p "$TMP/control"
dpkg-deb -e "$DEB" "$TMP/control"
for script in postinst postrm; do
  [ -x "$TMP/control/$script" ] || bad "the package has no executable $script"
done
if [ -x "$TMP/control/postinst" ]; then
  if command -v systemd-sysusers >/dev/null; then
    mkdir -p "$TMP/etc"
    DPKG_ROOT="$TMP" "$TMP/control/postinst" configure >"$TMP/postinst.log" 2>&1 ||
      bad "postinst configure failed: $(tail -2 "$TMP/postinst.log")"
    grep -q '^input:' "$TMP/etc/group" 2>/dev/null ||
      bad "postinst did not make the input group (systemd-sysusers igms.conf)"
  fi
  mkdir -p "$TMP/nosystemd"
  ln -s "$(command -v sh)" "$TMP/nosystemd/sh"
  PATH="$TMP/nosystemd" DPKG_ROOT="$TMP" "$TMP/control/postinst" configure >"$TMP/postinst.log" 2>&1 ||
    bad "postinst failed without systemd-sysusers: $(tail -2 "$TMP/postinst.log")"
  "$TMP/control/postrm" remove >"$TMP/postrm.log" 2>&1 ||
    bad "postrm remove failed: $(tail -2 "$TMP/postrm.log")"
fi
[ "$failures" = 0 ] || { say "$failures checks failed"; exit 1; }
echo "$DEB"
