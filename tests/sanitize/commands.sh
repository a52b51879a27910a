#!/usr/bin/env bash
# Every command of cutdyn once, and every reader once with good and with bad input, under the
# instrumented command line of the fuzz build (AddressSanitizer with leak detection and
# UndefinedBehaviorSanitizer; docs/sanitizers.md). `./run test` runs it after the fuzz targets.
#   tests/sanitize/commands.sh BINARY
# Exit status 1 if any run trips a sanitizer or exits with another status than expected (0 for
# good input, 2 for bad input); one line per run.
set -uo pipefail
cd "$(dirname "$0")/../.."
BIN=$(realpath "$1")
WORK=$(mktemp -d "${TMPDIR:-/tmp}/cutdyn-sanitize.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
# A finding exits with 86 (never one of cutdyn's own statuses) and is printed to stderr.
export ASAN_OPTIONS=exitcode=86:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=exitcode=86:halt_on_error=1:print_stacktrace=1
failed=0
ran=0

# expect STATUS NAME ARGS...: runs BIN ARGS in $WORK with a time limit.
expect() {
  local want=$1 name=$2 got start
  shift 2
  start=$(date +%s.%N)
  (cd "$WORK" && timeout 300 "$BIN" "$@" >"$WORK/$name.out" 2>"$WORK/$name.err" </dev/null)
  got=$?
  ran=$((ran + 1))
  local seconds
  seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  if [ "$got" -ne "$want" ] || grep -qE 'Sanitizer|runtime error' "$WORK/$name.err"; then
    failed=$((failed + 1))
    printf 'sanitize %-28s FAILED (exit %s, expected %s, %s s)\n' "$name" "$got" "$want" "$seconds"
    grep -m12 -E 'ERROR|runtime error|SUMMARY|#[0-9] |error' "$WORK/$name.err" | sed 's/^/    /'
  else
    printf 'sanitize %-28s ok (exit %s, %s s)\n' "$name" "$got" "$seconds"
  fi
}

# Inputs: a milling case with 24 speeds (the built-in one has 200: slow when instrumented), a
# current log of two axes at two steady speeds each, and bad files of each kind.
"$BIN" example milling-insperger | sed 's/^rpm_steps = 200/rpm_steps = 24/' >"$WORK/milling.toml"
grep -q '^rpm_steps = 24' "$WORK/milling.toml" ||
  { echo "sanitize: no rpm_steps in the example"; exit 1; }
awk 'BEGIN {
  print "time_s,axis,iu_a,iv_a,iw_a,speed_rad_s"
  for (i = 0; i < 4000; i++) {
    t = i * 0.001; a = 2 + sin(t * 40); th = t * 300; fast = t >= 2 ? 30 : 0
    u = a * cos(th); v = a * cos(th - 2.0944); w = a * cos(th + 2.0944)
    printf "%.3f,x,%.5f,%.5f,%.5f,%.3f\n", t, u, v, w, 50 + fast
    printf "%.3f,y,%.5f,%.5f,%.5f,%.3f\n", t, u, v, w, -40 - fast
  }
}' >"$WORK/log.csv"
printf 'process = "milling"\n[[modes]\nnatural_hz = 922\n' >"$WORK/bad.toml"
{ head -200 "$WORK/log.csv"; echo '0.2,x,1,2'; tail -100 "$WORK/log.csv"; } >"$WORK/bad-log.csv"
printf 'frequency_hz,real,imag\n100,1e-7,-2e-7\n200,abc,-1e-7\n' >"$WORK/bad-frf.csv"
printf 'feed_per_tooth_mm,depth_mm,fx_n,fy_n\n0.05,2,100\n' >"$WORK/bad-forces.csv"

# Every command on good input.
expect 0 example-list example --list
expect 0 lobes-default lobes --out l.csv --json l.json
expect 0 lobes-milling lobes milling.toml --out lm.csv --plot lm.svg
expect 0 lobes-zero-order lobes milling.toml --method zero-order --out lz.csv
expect 0 check-milling check milling.toml --rpm 10000 --depth-mm 0.05 --json c.json
expect 0 check-turning check turning-ultrasonic --rpm 1400 --depth-mm 10
expect 0 simulate-turning simulate turning-ultrasonic --duration-s 0.05 --json st.json
expect 0 simulate-milling simulate milling.toml --duration-s 0.05 --out sm.csv
expect 0 force-ultrasonic force ultrasonic-force
expect 0 force-oxley force oxley-aisi1045
expect 0 drive drive ermolaev2020 --json d.json
expect 0 plan plan --json p.json
for f in tool_x.frf tool_x.csv tool_x.uff; do
  expect 0 "fit-${f#tool_x.}" fit "$PWD/examples/frf/$f" --out "fit-$f.toml"
done
expect 0 identify identify milling.toml "$PWD/examples/forces/milling-insperger-mean-forces.csv" \
  --json i.json
expect 0 monitor-calibrate monitor calibrate --base zheng2012 --idle log.csv --out calib.json
expect 0 monitor-teach monitor teach --calib zheng2012 log.csv --out band.json
expect 0 monitor-estimate monitor estimate --calib zheng2012 log.csv --band band.json --out e.csv \
  --alarms a.csv --json e.json
expect 0 monitor-estimate-skip monitor estimate --calib zheng2012 --on-bad-line skip bad-log.csv \
  --out es.csv
expect 0 sweep sweep milling.toml --vary 'modes[0].damping_ratio=0.01:0.01:0.02' --out sw.csv

# Bad input: a clear error, exit 2.
expect 2 bad-case lobes bad.toml
expect 2 bad-option check milling.toml --rpm -5 --depth-mm 0.05
expect 2 bad-log monitor estimate --calib zheng2012 bad-log.csv --out eb.csv
expect 2 bad-frf fit bad-frf.csv
expect 2 bad-forces identify milling.toml bad-forces.csv
expect 2 bad-calibration monitor estimate --calib log.csv log.csv

# serve: the page, a computation and a bad request, then SIGTERM.
(cd "$WORK" && exec "$BIN" serve milling.toml --port 0 >"$WORK/serve.out" 2>"$WORK/serve.err") &
server=$!
port=""
for _ in $(seq 1 300); do
  port=$(grep -o '127\.0\.0\.1:[0-9]*' "$WORK/serve.out" 2>/dev/null | head -1 | cut -d: -f2)
  [ -n "$port" ] && break
  sleep 0.1
done
ran=$((ran + 1))
if [ -z "$port" ] || ! python3 - "$port" <<'EOF'; then
import json, sys, urllib.request, urllib.error
base = "http://127.0.0.1:%s" % sys.argv[1]
opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
def post(path, body):
    request = urllib.request.Request(base + path, data=body, method="POST",
                                     headers={"Content-Type": "application/json"})
    try:
        with opener.open(request, timeout=120) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.read()
with opener.open(base + "/", timeout=60) as r:
    assert r.status == 200
with opener.open(base + "/api/case", timeout=60) as r:
    case = json.loads(r.read())["case"]
status, body = post("/api/check?rpm=10000&depth_mm=0.05", json.dumps(case).encode())
assert status == 200, (status, body[:300])
status, body = post("/api/lobes", b'{"process": "milling", ')
assert status == 400, (status, body[:300])
EOF
  failed=$((failed + 1))
  echo "sanitize serve                        FAILED (port '${port}')"
  sed 's/^/    /' "$WORK/serve.err" | head -20
fi
kill -TERM "$server" 2>/dev/null
wait "$server"
status=$?
if [ "$status" -eq 86 ] || grep -qE 'Sanitizer|runtime error' "$WORK/serve.err"; then
  failed=$((failed + 1))
  echo "sanitize serve                        FAILED (a finding; exit $status)"
  grep -m12 -E 'ERROR|runtime error|SUMMARY|#[0-9] ' "$WORK/serve.err" | sed 's/^/    /'
else
  echo "sanitize serve                        ok (exit $status after SIGTERM)"
fi

echo "sanitize: $((ran - failed)) of $ran runs clean"
[ "$failed" -eq 0 ]
