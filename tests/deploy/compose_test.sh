#!/usr/bin/env bash
# docker-compose.yml, its lab file and the Dockerfile, checked without a Docker engine:
# the compose lab file is deploy/lab.yaml derived by the shared generator (hosts and paths
# only), docker-compose's own validation passes, every serving process is a service that
# runs it, and the Dockerfile is a two-stage Debian 12 build whose run stage has no compiler.
TEST_NAME=deploy/compose
. "$(dirname "$0")/lib.sh"
cd "$SRC"

# The committed compose lab file is the generator's output today.
"$SRC/deploy/compose/derive-lab.sh" "$SCRATCH/lab.yaml" >/dev/null
check "deploy/compose/lab.yaml is derived from deploy/lab.yaml (rerun deploy/compose/derive-lab.sh)" \
  cmp -s "$SCRATCH/lab.yaml" deploy/compose/lab.yaml
# Line for line the same but for hosts and paths (and the note the generator puts first).
note_lines=$(($(wc -l <deploy/compose/lab.yaml) - $(wc -l <deploy/lab.yaml)))
changed=$(diff deploy/lab.yaml <(tail -n +$((note_lines + 1)) deploy/compose/lab.yaml) |
  grep -E '^[<>]' | grep -vE '^[<>] +(host|bind|calibration|database): ' || true)
check "only hosts, binds and paths differ from deploy/lab.yaml${changed:+: $changed}" test -z "$changed"
"$BIN/igms" config table --config deploy/compose/lab.yaml >"$SCRATCH/table" ||
  fail "igms config table cannot read deploy/compose/lab.yaml"

# docker-compose's own validation: unknown keys, wrong types (Debian's docker-compose also
# refuses a top-level name:).
if command -v docker-compose >/dev/null; then
  # `config` validates as `config -q` does, and prints the file as compose reads it.
  compose_config() { docker-compose -f docker-compose.yml config --no-interpolate >"$SCRATCH/compose.yaml"; }
  check "docker-compose config" compose_config
else
  note "SKIPPED docker-compose's validation: docker-compose is not installed"
  cp docker-compose.yml "$SCRATCH/compose.yaml"
fi
# One service per serving process, named as it, running it, on the lab network, with the
# derived lab file mounted read-only; the control client only in the operator profile.
python3 - "$SCRATCH/compose.yaml" "$SCRATCH/table" >"$SCRATCH/services-check" <<'PY' ||
import sys, yaml
compose = yaml.safe_load(open(sys.argv[1]))
services = compose.get("services", {})
problems = []
rows = [l.split() for l in open(sys.argv[2]).read().splitlines()[1:]]
for name, program, host, port in rows:
    s = services.get(name)
    if s is None:
        if port != "-":
            problems.append(f"{name}: no service")
        continue
    if port == "-" and "operator" not in s.get("profiles", []):
        problems.append(f"{name}: a client, but not in the operator profile")
    cmd = s.get("command", [])
    if not cmd or cmd[0] != name:
        problems.append(f"{name}: its command does not run it ({cmd})")
    if port != "-" and host != name:
        problems.append(f"{name}: the lab file's host is {host}, not the service's name")
    if "lab" not in (s.get("networks") or {}):
        problems.append(f"{name}: not on the lab network")
    vols = s.get("volumes", [])
    text = [v if isinstance(v, str) else f'{v.get("source")}:{v.get("target")}:{"ro" if v.get("read_only") else "rw"}' for v in vols]
    if not any(t.endswith("deploy/compose/lab.yaml:/etc/igms/lab.yaml:ro") for t in text):
        problems.append(f"{name}: the lab file is not mounted read-only at /etc/igms/lab.yaml ({text})")
for name in services:
    if name not in [r[0] for r in rows]:
        problems.append(f"{name}: a service with no process in the lab file")
if problems: print("\n".join(problems))
PY
  echo "the check itself failed" >>"$SCRATCH/services-check"
check "every process is its service$(sed 's/^/; /' "$SCRATCH/services-check" | tr -d '\n')" \
  test ! -s "$SCRATCH/services-check"

# The Dockerfile.
D=Dockerfile
bad=$(grep -vE '^\s*(#|$)' $D | grep -E '^[A-Za-z]+ ' | awk '{ print toupper($1) }' |
  grep -vxE 'FROM|RUN|COPY|ADD|ENV|ARG|WORKDIR|USER|VOLUME|EXPOSE|ENTRYPOINT|CMD|LABEL|HEALTHCHECK|STOPSIGNAL|SHELL|ONBUILD' || true)
check "Dockerfile: known instructions only${bad:+ ($bad)}" test -z "$bad"
froms=$(grep -E '^FROM ' $D)
check "Dockerfile: every stage is Debian 12 (bookworm)" \
  bash -c "! grep -vE '^FROM debian:bookworm(-slim)?( AS [a-z]+)?\$' <<<'$froms'"
check "Dockerfile: two stages or more" test "$(grep -c . <<<"$froms")" -ge 2
stages=$(sed -nE 's/^FROM .* AS ([a-z]+)$/\1/p' $D)
for from in $(sed -nE 's/^COPY --from=([^ ]+) .*/\1/p' $D); do
  check "Dockerfile: COPY --from=$from names an earlier stage" grep -qxF "$from" <<<"$stages"
done
# Sources of COPY without --from exist in the build context.
while read -r line; do
  set -- $line
  shift
  while [ $# -gt 1 ]; do
    check "Dockerfile: COPY source $1 exists" test -e "$SRC/$1"
    shift
  done
done < <(grep -E '^COPY ' $D | grep -v -- '--from')
# The run stage (the last): only the run-time packages, no compiler.
last=$(awk '/^FROM /{ buf = "" } { buf = buf $0 "\n" } END { printf "%s", buf }' $D)
check "Dockerfile: the run stage installs install-deps.sh --runtime" grep -q 'install-deps.sh --runtime' <<<"$last"
compilers=$(grep -E '^RUN' <<<"$last" | grep -oE '\b(g\+\+|gcc|clang|cmake|ninja|build-essential)\b' || true)
check "Dockerfile: no compiler or build tool named in the run stage${compilers:+: $compilers}" \
  test -z "$compilers"
runtime=$("$SRC/deploy/install-deps.sh" --runtime --list)
check "install-deps.sh --runtime lists packages" test -n "$runtime"
dev=$(grep -E -- '-dev$|^(g\+\+|gcc|cpp|clang.*|cmake|ninja-build|make)$' <<<"$runtime" || true)
check "the run-time packages hold no compiler or headers${dev:+: $dev}" test -z "$dev"
# Every library the built programs load directly comes from a --runtime package (libc's
# own and the compiler's support library are in every Debian system).
needed=$(for f in "$BIN"/*; do readelf -d "$f" 2>/dev/null | sed -nE 's/.*\(NEEDED\).*\[(.*)\]/\1/p'; done |
  sort -u | grep -vE '^(libc|libm|libgcc_s|ld-linux.*)\.so' || true)
paths=$(ldconfig -p | awk -v want="$(tr '\n' ' ' <<<"$needed")" '
  BEGIN { n = split(want, w, " "); for (i = 1; i <= n; i++) keep[w[i]] = 1 }
  $1 in keep && /x86-64|x86_64/ && !seen[$1]++ { print $NF }')
owners=$(for p in $paths; do readlink -f "$p"; done | xargs dpkg -S 2>/dev/null | cut -d: -f1 | sort -u)
missing=$(comm -23 <(echo "$owners") <(sort <<<"$runtime") | tr '\n' ' ' | sed 's/ $//')
check "the programs' libraries are all in install-deps.sh --runtime${missing:+ (missing: $missing)}" \
  test -n "$owners" -a -z "$missing"
finish
