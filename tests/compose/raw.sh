# The raw profile's check, sourced by tests/compose/run.sh (its helpers): docker-compose.raw.yml renders
# the default room's raw signals (RAW_DURATION s: camera frames, microphone-pair audio, LIDAR scans) and
# every agent runs its real front end on them (edge-agent camera --frames, mic-pair --wav, lidar --scans).
#   raw: end to end    the tracks of all seven sensors scored against the renderer's truth once everybody
#                      is in: mean OSPA <= RAW_MAX_OSPA (0.5 m); every sensor's sets processed, the share
#                      that came too late printed (a front end slower than real time on a busy host)
#   raw: agents end    every agent ends with its input by itself (exit 0), none restarted

start_project "fusionraw$$" -f "$repo/docker/docker-compose.raw.yml"
export RAW_DURATION="${RAW_DURATION:-24}"
section "10. raw signals: each agent's real front end on rendered frames, audio and scans ($RAW_DURATION s)"
echo "  project $project, SEED $SEED"
raw_origin() { dc logs --no-color render 2>/dev/null | grep -o 'scenario time 0 is Unix time [0-9.]*' | awk '{ print $NF }' || true; }
if out="$(dc up -d 2>&1)"; then
  origin=""
  for _ in $(seq 1 600); do # rendering takes a minute or two on two cores
    origin="$(raw_origin)"
    [ -n "$origin" ] && break
    sleep 0.5
  done
  dc logs --no-color render 2>/dev/null | grep -E 'rendering took|scenario time 0' | sed 's/^[^|]*| /    /' || true
  if [ -z "$origin" ]; then
    fail "raw: the renderer did not finish within 300 s"
  else
    while le "$(now)" "$(awk -v o="$origin" -v d="$ALL_IN_VIEW_S" 'BEGIN { printf "%.3f", o + d }')"; do sleep 0.5; done
    watch_ospa "raw: end to end, all seven sensors from raw signals" 12 "${RAW_MAX_OSPA:-0.5}"
    raw_status="$(status_json)" || raw_status=""
    inspect status-sensors <<<"$raw_status" | sed 's/^/    alive received processed late invalid lost: /'
    if [ -n "$raw_status" ] && ! inspect status-sensors <<<"$raw_status" | awk '$4 <= 0 { bad = 1 } END { exit !(NR == 7 && !bad) }'; then
      fail "raw: a sensor's sets were not processed"
    elif [ -n "$raw_status" ]; then
      pass "raw: every sensor's sets processed ($(inspect status-sensors <<<"$raw_status" | awk '{ r += $3; l += $5 } END { printf "%d of %d too late", l, r }'))"
    else
      fail "raw: no status reply"
    fi
    # The agents end with their input, RAW_DURATION s after the origin (cameras 1 s before it).
    while le "$(now)" "$(awk -v o="$origin" -v d="$RAW_DURATION" 'BEGIN { printf "%.3f", o + d + 10 }')"; do sleep 1; done
    ended=1
    for s in "${SENSORS[@]}"; do
      state="$(docker inspect --format '{{.State.Status}} {{.State.ExitCode}} {{.RestartCount}}' "$(container_of "$s")")"
      [ "$state" = "exited 0 0" ] || { echo "    $s: $state (status, exit code, restarts)"; ended=0; }
    done
    if [ "$ended" = 1 ]; then
      pass "raw: agents end: all 7 agents ended with their input (exit 0), none restarted"
    else
      fail "raw: agents end: an agent is still running, failed or was restarted"
    fi
  fi
else
  echo "$out"
  fail "raw: compose up failed"
fi
section "raw profile: down"
down_project
