#!/usr/bin/env bash
# Fault and security tests of the Docker deployment (docker/README.md says what each checks).
# Needs the images of docker/build.sh. Brings the stack up under a unique project name, injects faults
# with docker commands, measures with fusion-checker containers, prints every figure, tears everything
# down (volumes included) on exit, and exits non-zero when any check failed.
#   tests/compose/run.sh              # all checks, about 6 minutes
#   KEEP_LOGS=1 tests/compose/run.sh   # print the services' logs at the end even when all passed
#   ONLY=secure,sites tests/compose/run.sh   # only these parts, of: plain (checks 1 to 6), secure (7: mTLS,
#                                            # passwords, access control), standby (8), sites (9), raw (10)
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
plain=(-f "$repo/docker/docker-compose.yml")
secure=(-f "$repo/docker/docker-compose.yml" -f "$repo/docker/docker-compose.secure.yml")
standby=(-f "$repo/docker/docker-compose.yml" -f "$repo/docker/docker-compose.standby.yml")
sites=(-f "$repo/docker/docker-compose.sites.yml")
ONLY="${ONLY:-plain,secure,standby,sites,raw}"
want() { [[ ",$ONLY," == *",$1,"* ]]; }
inspect() { python3 "$here/inspect_output.py" "$@"; }

export SEED="${SEED:-7}"
export START=0 # set for real by bring_up; compose needs a value even to tear a project down
export FUSION_IMAGE_TAG="${FUSION_IMAGE_TAG:-latest}"
# fusion-view's port on the host: a free one, so that the tests never collide with a view already running.
export VIEW_PORT="${VIEW_PORT:-$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')}"
SENSORS=(cam1 cam2 mics_n mics_e mics_s mics_w lidar)
# The long-running services of the project under test (start_project sets them).
SERVICES=(router server "${SENSORS[@]}")
# People enter the default room at 0.5, 2 and 4.5 s; their tracks need a few sets to be confirmed.
ALL_IN_VIEW_S=8

# Compose v2 (`docker compose`) when present, else v1 (`docker-compose`): both read these files.
if docker compose version >/dev/null 2>&1; then
  COMPOSE=(docker compose)
else
  COMPOSE=(docker-compose)
fi

# ------------------------------------------------------------------ bookkeeping
results=()
failed=0
began=$SECONDS
pass() { results+=("PASS  $1"); printf '  PASS  %s\n' "$1"; }
fail() { results+=("FAIL  $1"); printf '  FAIL  %s\n' "$1"; failed=1; }
section() { printf '\n=== %s (t = %d s)\n' "$1" "$((SECONDS - began))"; }
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }
# `le A B` is true when the number A is at most B.
le() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a <= b) }'; }

# The project under test; `dc` runs compose on it with the current file set.
project=""
files=()
projects=()
declare -A project_files
dc() { "${COMPOSE[@]}" -p "$project" "${files[@]}" "$@"; }
start_project() { # name, files...
  project="$1"
  shift
  files=("$@")
  projects+=("$project")
  project_files[$project]="$*"
  SERVICES=(router server "${SENSORS[@]}")
}

summary() {
  section "summary"
  printf '%s\n' "${results[@]}"
  local passed
  passed=$(printf '%s\n' "${results[@]}" | grep -c '^PASS' || true)
  printf '\n%d checks, %d passed, %d failed, %d s\n' "${#results[@]}" "$passed" "$((${#results[@]} - passed))" "$((SECONDS - began))"
}

# On any exit: logs when something failed, everything removed (volumes too), then the summary.
finished=0
teardown() {
  local code=$?
  if [ "$finished" = 0 ]; then
    fail "the script stopped early (exit $code) after the last check above"
  fi
  local p f
  for p in "${projects[@]}"; do
    read -r -a f <<<"${project_files[$p]}"
    if [ "$failed" = 1 ] || [ "${KEEP_LOGS:-0}" = 1 ]; then
      printf '\n--- logs of %s (last 25 lines per service)\n' "$p"
      "${COMPOSE[@]}" -p "$p" "${f[@]}" logs --no-color --tail 25 2>/dev/null || true
    fi
    "${COMPOSE[@]}" -p "$p" "${f[@]}" down -v --remove-orphans >/dev/null 2>&1 || true
  done
  summary
  exit "$failed"
}
trap teardown EXIT

# The checker as a one-off container of the project (its network, its credentials). `checker` keeps its
# messages (minus compose's own), `checker_json` only stdout, for parsing.
checker() {
  local log rc=0
  log="$(dc run --rm -T checker "$@" 2>&1)" || rc=$?
  grep -v -e '^Creating ' -e '^Starting ' <<<"$log" || true
  return "$rc"
}
checker_json() { dc run --rm -T checker "$@" 2>/dev/null; }
# The server's status as JSON; a query that gets no answer (a checker container started on a busy host)
# is asked again, up to three times in all.
status_json() {
  local attempt
  for attempt in 1 2 3; do
    checker_json status && return 0
    [ "$attempt" = 3 ] || sleep 1
  done
  return 1
}
container_of() { dc ps -q "$1"; }
# Takes the project under test down (volumes too), after its services' last logs when a check failed.
down_project() {
  if [ "$failed" = 1 ] || [ "${KEEP_LOGS:-0}" = 1 ]; then
    printf '\n--- logs of %s (last 25 lines per service)\n' "$project"
    dc logs --no-color --tail 25 2>/dev/null || true
  fi
  dc down -v --remove-orphans >/dev/null 2>&1 || true
}

# The `status` line of one sensor: "alive received processed late invalid lost" ("no-status" when the
# server did not answer).
sensor_status() {
  local out
  out="$(status_json)" || { echo "no-status"; return 0; }
  inspect status-sensor "$1" <<<"$out"
}
# The server-wide rejection counters: "undecodable unknown_sensor invalid late".
rejected_counts() {
  local out
  out="$(status_json)" || { echo "na na na na"; return 0; }
  inspect status-rejected <<<"$out"
}
field() { # field N of a sensor_status line (1 = alive, 2 = received, 3 = processed)
  awk -v n="$2" '{ print $n }' <<<"$1"
}

# Container state, to tell a crash (restart policy: RestartCount grows, StartedAt moves) from our own doing.
declare -A started_at
record_started() {
  local s
  for s in "${SERVICES[@]}"; do
    started_at[$s]="$(docker inspect --format '{{.State.StartedAt}}' "$(container_of "$s")")"
  done
}
# Every service running, none restarted by its policy, and none (re)started except those named.
check_no_restarts() { # label, services we restarted ourselves...
  local label="$1" s cid state ok=1
  shift
  for s in "${SERVICES[@]}"; do
    cid="$(container_of "$s")"
    state="$(docker inspect --format '{{.State.Status}} {{.RestartCount}} {{.State.StartedAt}}' "$cid")"
    read -r status restarts started <<<"$state"
    if [ "$status" != running ] || [ "$restarts" != 0 ]; then
      echo "    $s: $status, RestartCount $restarts; its errors (the log spans every run of the container):"
      docker logs "$cid" 2>&1 | grep -iE "error|panic|fatal|killed" | tail -n 15 | sed 's/^/      /'
      ok=0
    elif [ "$started" != "${started_at[$s]}" ] && [[ " $* " != *" $s "* ]]; then
      echo "    $s: restarted by itself (StartedAt ${started_at[$s]} -> $started)"
      ok=0
    fi
  done
  if [ "$ok" = 1 ]; then
    pass "$label: all ${#SERVICES[@]} containers running, RestartCount 0, none restarted by itself"
  else
    fail "$label: a container crashed or restarted"
  fi
  record_started
}

# Polls the status until sensor $1's line satisfies the awk condition $2 (on $1 alive, $2 received,
# $3 processed), for at most $3 seconds. Prints the elapsed time; fails when it never did.
wait_sensor() {
  local sensor="$1" condition="$2" timeout="$3" t0 line
  t0="$(now)"
  while :; do
    line="$(sensor_status "$sensor" || true)"
    if [ -n "$line" ] && awk "{ exit !($condition) }" <<<"$line"; then
      echo "$(elapsed "$t0") $line"
      return 0
    fi
    if ! le "$(elapsed "$t0")" "$timeout"; then
      echo "$(elapsed "$t0") $line"
      return 1
    fi
    sleep 0.3
  done
}

# Brings a stack up with a fresh start time and waits for its tracks.
bring_up() { # label
  START=$(($(date +%s) + 3))
  export START
  echo "  project $project, START $START, SEED $SEED (${COMPOSE[*]})"
  local out
  if ! out="$(dc up -d --quiet-pull 2>&1)"; then
    echo "$out"
    fail "$1: compose up failed"
    return 1
  fi
  if out="$(checker wait-tracks --timeout 60)"; then
    pass "$1: $out (checker started right after up)"
  else
    fail "$1: no tracks within 60 s ($out)"
    return 1
  fi
  record_started
  # Score only once everybody is in the room and confirmed.
  while [ "$(date +%s)" -lt $((START + ALL_IN_VIEW_S)) ]; do sleep 0.5; done
}

# `watch` for $1 seconds, require mean OSPA <= $2; prints the checker's figures.
watch_ospa() { # label, seconds, max ospa
  local out code=0
  out="$(checker watch --duration "$2" --max-ospa "$3")" || code=$?
  sed 's/^/    /' <<<"$out"
  local ospa
  ospa="$(grep -o 'mean OSPA [0-9.]* m' <<<"$out" | head -1 | awk '{ print $3 }')"
  if [ "$code" = 0 ] && [ -n "$ospa" ]; then
    pass "$1: mean OSPA $ospa m <= $3 m over $2 s"
  else
    fail "$1: mean OSPA ${ospa:-n/a} m, limit $3 m over $2 s"
  fi
}

all_sensors_alive() { # label
  local out s line ok=1
  out="$(status_json)" || { fail "$1: no status reply"; return; }
  for s in "${SENSORS[@]}"; do
    line="$(inspect status-sensor "$s" <<<"$out")"
    printf '    %-7s alive received processed late invalid lost: %s\n' "$s" "$line"
    if [ "$(field "$line" 1)" != true ] || [ "$(field "$line" 3)" -le 0 ] 2>/dev/null; then ok=0; fi
  done
  if [ "$ok" = 1 ]; then
    pass "$1: all 7 sensors alive and counted (processed > 0)"
  else
    fail "$1: a sensor is not alive or not counted"
  fi
}

# ================================================================== plain profile
if want plain; then
start_project "fusiontest$$" "${plain[@]}"
section "plain profile: up"
bring_up "startup"

section "1. steady state"
watch_ospa "steady state" 30 0.2
all_sensors_alive "steady state"

section "1b. the browser view (fusion-view) on the host's port $VIEW_PORT"
view_url="http://127.0.0.1:$VIEW_PORT"
if page="$(curl -fsS --max-time 5 "$view_url/")" && grep -q 'id="tracks"' <<<"$page" &&
  scene="$(curl -fsS --max-time 5 "$view_url/api/scene")"; then
  read -r view_tracks view_sensors view_alive view_site view_truth <<<"$(inspect view-scene <<<"$scene")"
  echo "    $view_url/: site $view_site, $view_tracks tracks, $view_truth people in the truth, $view_sensors sensors ($view_alive alive)"
  # The people in the room at this moment (the scenario's third person leaves at 52 s).
  if [ "$view_tracks" -gt 0 ] && [ "$view_tracks" = "$view_truth" ] && [ "$view_sensors" = 7 ] && [ "$view_alive" = 7 ]; then
    pass "view: the page is served and its scene has a track per person ($view_tracks) and 7 live sensors"
  else
    fail "view: expected a track per person of the truth ($view_truth) and 7 live sensors in the scene"
  fi
else
  fail "view: $view_url did not serve the page and its scene"
fi

section "2. partition: mics_n cut off the network for 10 s"
network="$(docker inspect --format '{{range $k, $v := .NetworkSettings.Networks}}{{$k}} {{end}}' "$(container_of mics_n)" | awk '{ print $1 }')"
before="$(sensor_status mics_n)"
echo "    before: alive received processed late invalid lost: $before"
docker network disconnect "$network" "$(container_of mics_n)"
sleep 10
during="$(sensor_status mics_n)"
echo "    after 10 s cut off: $during"
docker network connect "$network" "$(container_of mics_n)"
t_back="$(now)"
# Resumed: more sets received than when the cut ended, and alive again.
if resumed="$(wait_sensor mics_n "\$1 == \"true\" && \$2 > $(field "$during" 2)" 30)"; then
  pass "partition: mics_n publishing again $(field "$resumed" 1) s after reconnecting (received $(field "$during" 2) -> $(field "$resumed" 3))"
else
  fail "partition: mics_n did not resume within 30 s (last: $resumed)"
fi
check_no_restarts "partition"

section "3. server restart: track ids kept (checkpoint on the named volume)"
# The checkpoint restores every label, but the filter itself may relabel a person after a gap in its data
# (a restart is a gap of about half a second): always while two people are within about half a metre, and
# now and then otherwise (reproduced offline with gaps cut into a replay file, no restart involved;
# gmphd's identity rules have since made the latter rare: a still person keeps the label across such
# gaps in 196 of 200 simulated runs, gmphd/tests/label_after_gap.rs; close pairs were not re-measured).
# So the restart is done while everybody stays apart, and tried up to
# three times: a broken checkpoint fails every attempt (all ids change), the filter's relabelling seldom
# twice. The truth is a pure function of (scenario, seed, time): the agent image computes it, offline.
windows="$(docker run --rm "fusion/edge-agent:$FUSION_IMAGE_TAG" sim --sensor lidar --truth --seed "$SEED" \
  --start 0 --duration 300 --output - 2>/dev/null | inspect apart-windows 0.7 14)"
echo "    stretches of scenario time with everybody at least 0.7 m apart: $(tr '\n' ' ' <<<"$windows")"
restart_keeps_ids() { # attempt number; true when every person kept their id
  local before after compared downtime t0 code=0
  before="$(mktemp)"
  after="$(mktemp)"
  checker_json ids --duration 3 >"$before" || true
  t0="$(now)"
  dc restart -t 15 server >/dev/null 2>&1
  checker wait-tracks --timeout 20 >/dev/null || true
  local back
  back="$(elapsed "$t0")"
  # The data gap the filter saw: from the old process's shutdown to the new one's session.
  downtime="$(dc logs --no-color server 2>/dev/null | grep -e 'shutting down' -e 'zenoh session open' | tail -2 |
    grep -o '20[0-9-]*T[0-9:.]*Z' | while read -r stamp; do date -d "$stamp" +%s.%N; done |
    awk 'NR == 1 { a = $1 } NR == 2 { printf "%.2f", $1 - a }')"
  checker_json ids --duration 3 >"$after" || true
  echo "    attempt $1 at t = $(($(date +%s) - START)) s: server down ${downtime:-?} s, tracks seen again $back s after the restart began"
  echo "      ids before: $(cat "$before")"
  echo "      ids after:  $(cat "$after")"
  compared="$(inspect ids-compare "$before" "$after")" || code=$?
  sed 's/^/      /' <<<"$compared"
  last_comparison="$(tail -1 <<<"$compared")"
  rm -f "$before" "$after"
  return "$code"
}
kept=0
attempt=0
while [ "$attempt" -lt 3 ] && [ "$kept" = 0 ]; do
  scenario_now=$(($(date +%s) - START))
  # The next moment from which a stretch has at least 13 s left (one attempt takes about that long).
  slot="$(awk -v now="$scenario_now" '{ s = ($1 > now ? $1 : now); if ($2 - s >= 13) { print s; exit } }' <<<"$windows")"
  if [ -z "$slot" ]; then
    [ "$attempt" -gt 0 ] && break
    echo "    no stretch with everybody apart ahead: restarting now"
  else
    while le "$(($(date +%s) - START))" "$slot"; do sleep 0.5; done
  fi
  attempt=$((attempt + 1))
  if restart_keeps_ids "$attempt"; then kept=1; fi
done
if [ "$kept" = 1 ]; then
  pass "server restart: $last_comparison (attempt $attempt of at most 3)"
else
  fail "server restart: track ids not kept in $attempt attempts ($last_comparison)"
fi
check_no_restarts "server restart" server

section "4. sensor loss: cam1 stopped, then started again"
dc stop cam1 >/dev/null 2>&1
if gone="$(wait_sensor cam1 '$1 == "false"' 10)"; then
  pass "sensor loss: status shows cam1 not alive ($(field "$gone" 1) s after the stop)"
else
  fail "sensor loss: cam1 still alive 10 s after the stop ($gone)"
fi
watch_ospa "sensor loss (6 sensors)" 10 0.3
stopped="$(sensor_status cam1)"
dc start cam1 >/dev/null 2>&1
# Rejoined: alive, and processing live sets (its catch-up burst of past frames only counts as late).
if back="$(wait_sensor cam1 "\$1 == \"true\" && \$3 > $(field "$stopped" 3)" 5)"; then
  first_processed="$(field "$back" 4)"
  sleep 1
  again="$(sensor_status cam1)"
  if [ "$(field "$again" 3)" -gt "$first_processed" ]; then
    pass "sensor loss: cam1 rejoined $(field "$back" 1) s after its start (alive, processed $(field "$stopped" 3) -> $first_processed -> $(field "$again" 3))"
  else
    fail "sensor loss: cam1 alive but its processed count stopped at $first_processed"
  fi
else
  fail "sensor loss: cam1 did not rejoin within 5 s (last: $back)"
fi
record_started

section "5. router restart"
t0="$(now)"
dc restart router >/dev/null 2>&1
restarted_in="$(elapsed "$t0")"
t1="$(now)"
if out="$(checker wait-tracks --timeout 10)"; then
  flow="$(elapsed "$t1")"
  if le "$flow" 10; then
    pass "router restart: tracks flowing again $flow s after the router was back (docker restart took $restarted_in s)"
  else
    fail "router restart: tracks took $flow s (> 10 s) after the router was back"
  fi
else
  fail "router restart: no tracks within 10 s after the router was back ($out)"
fi
sleep 2
all_sensors_alive "router restart"
check_no_restarts "router restart" router

section "6. bad input: a rogue floods garbage, invalid and unknown-sensor sets for 10 s"
read -r und0 unk0 inv0 late0 <<<"$(rejected_counts)"
rogue_log="$(mktemp)"
checker rogue --victim cam1 --duration 10 --rate 200 >"$rogue_log" 2>&1 &
rogue_pid=$!
sleep 1
watch_ospa "bad input (during the flood)" 10 0.2
wait "$rogue_pid" || fail "bad input: the rogue checker itself failed"
sed 's/^/    /' "$rogue_log"
rm -f "$rogue_log"
read -r und1 unk1 inv1 late1 <<<"$(rejected_counts)"
echo "    rejected: undecodable $und0 -> $und1, unknown_sensor $unk0 -> $unk1, invalid $inv0 -> $inv1, late $late0 -> $late1"
if [ "$und1" -gt "$und0" ] && [ "$unk1" -gt "$unk0" ] && [ "$inv1" -gt "$inv0" ]; then
  pass "bad input: counted in status (undecodable +$((und1 - und0)), unknown sensor +$((unk1 - unk0)), invalid +$((inv1 - inv0)))"
else
  fail "bad input: not all kinds counted in status"
fi
check_no_restarts "bad input"

section "plain profile: down"
down_project
fi

# ================================================================== secure profile
if want secure; then
start_project "fusionsecure$$" "${secure[@]}"
section "7. secure profile: mutual TLS, user/password and access control on the router"
bring_up "secure startup (agents and server with credentials)"
watch_ospa "secure: honest agents with credentials" 10 0.2
all_sensors_alive "secure"
read -r und0 unk0 inv0 late0 <<<"$(rejected_counts)"
# A rogue must fail to open its session; the reason shows where: plain TCP on the TLS port (dropped), the
# TLS handshake (no client certificate), or the router closing Zenoh's handshake at OpenSyn (a valid
# certificate but a wrong password's HMAC).
refused() { # service, label, checker arguments...
  local service="$1" label="$2" out code=0 reason
  shift 2
  out="$(dc run --rm -T -e NO_COLOR=1 "$service" "$@" 2>&1)" || code=$?
  reason="$(grep -o -m1 -e 'Received a close message ([^)]*) in response to an [A-Za-z]*' \
    -e 'Connection refused' -e 'early eof' -e 'Unable to connect to any of' <<<"$out" || true)"
  [ "$reason" = "early eof" ] && reason="the TLS listener dropped the plain TCP connection: early eof"
  # The router logs "peer sent no certificates" and ends the TLS handshake: the link never opens.
  [ "$reason" = "Unable to connect to any of" ] && reason="mutual TLS: the router ended the TLS handshake, no client certificate"
  if [ "$code" != 0 ] && grep -q "opening the zenoh session failed" <<<"$out"; then
    pass "secure: $label: refused at session open (${reason:-no reason logged})"
  else
    fail "secure: $label: NOT refused (exit $code): $(tail -2 <<<"$out")"
  fi
}
refused rogue-plain "plain TCP client reading tracks" tracks
refused rogue-anonymous "TLS client without a certificate or credentials reading tracks" tracks
refused rogue-anonymous "TLS client without a certificate or credentials publishing measurements" rogue --victim cam1 --duration 3
refused rogue-wrong-password "TLS client with a valid certificate but a wrong password reading tracks" tracks
read -r und1 unk1 inv1 late1 <<<"$(rejected_counts)"
if [ "$und1" = "$und0" ] && [ "$unk1" = "$unk0" ] && [ "$inv1" = "$inv0" ]; then
  pass "secure: nothing of the rogues reached the server (rejected counters unchanged: $und1 $unk1 $inv1)"
else
  fail "secure: rejected counters moved ($und0 $unk0 $inv0 -> $und1 $unk1 $inv1)"
fi
source "$here/access_control.sh"
check_no_restarts "secure"
section "secure profile: down"
down_project
fi

# ================================================================== hot standby, many sites, raw signals (then the summary, on exit)
for part in standby sites raw; do want "$part" && source "$here/$part.sh"; done
finished=1
