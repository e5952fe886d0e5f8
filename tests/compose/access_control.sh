# The access-control checks of the secure profile, sourced by tests/compose/run.sh (its helpers, its
# project up): an identity that may connect writes where it may not, while a sniffer (the checker's
# identity, which may read everything) listens to everything of the site and asks for its status.
#   acl: impersonation refused   the agent cam1's certificate and password: forged sets on lidar's key,
#                                forged track sets on fusion/default/tracks(/json), a fake status queryable
#   acl: client cannot publish   the checker's own identity doing the same
# Passes when no forged message reached the sniffer, no forged status answered, the server's counters
# (lidar's invalid and lost, the rejections) did not move, and the router logged the refusals (Zenoh
# 1.10 logs every access-control decision at trace level, target
# zenoh::net::routing::interceptor::access_control: "<zid> on Interface(eth0)+CertCommonName(default/cam1)+
# Username(edge-agent)+Transport(Tls)+<zid> is unauthorized to Put (ingress) on <key>").

# "puts on lidar's key, puts on the tracks keys, status queryables" refused so far to the identity whose
# certificate's common name is $1, from the router's log (the subject names the common name).
refusals() {
  local log
  log="$(dc logs --no-color router 2>/dev/null | grep -F "CertCommonName($1)" || true)"
  printf '%s %s %s\n' \
    "$(grep -c 'unauthorized to Put (ingress) on fusion/default/sensors/lidar/measurements' <<<"$log" || true)" \
    "$(grep -c 'unauthorized to Put (ingress) on fusion/default/tracks' <<<"$log" || true)" \
    "$(grep -c -E 'unauthorized to Declare(/Undeclare)? Queryable \(ingress\) on fusion/default/status' <<<"$log" || true)"
}

acl_probe() { # label, service playing the impostor, its certificate's common name
  local label="$1" service="$2" cn="$3" sniffed tried lidar0 lidar1 rej0 rej1 code=0 set0 tracks0 queryable0
  read -r set0 tracks0 queryable0 <<<"$(refusals "$cn")"
  lidar0="$(sensor_status lidar)"
  rej0="$(rejected_counts)"
  sniffed="$(mktemp)"
  checker_json sniff --duration 8 >"$sniffed" &
  local sniffer=$!
  sleep 1.5
  tried="$(dc run --rm -T "$service" impersonate --victim lidar --duration 5 --rate 20 2>/dev/null)" || code=$?
  wait "$sniffer" || true
  lidar1="$(sensor_status lidar)"
  rej1="$(rejected_counts)"
  local forged forged_status genuine_lidar genuine_tracks replies puts answered
  read -r forged forged_status genuine_lidar genuine_tracks replies <<<"$(inspect sniff lidar <"$sniffed" 2>/dev/null || echo "na na na na na")"
  read -r puts answered <<<"$(inspect impostor <<<"$tried" 2>/dev/null || echo "na na")"
  rm -f "$sniffed"
  echo "    $service (exit $code) tried $puts puts (forged lidar sets, track sets, JSON track sets); its fake status queryable was asked $answered times"
  echo "    sniffer (checker identity): $forged forged samples, $forged_status forged status replies of $replies; genuine: $genuine_lidar lidar sets, $genuine_tracks track sets"
  echo "    lidar alive received processed late invalid lost: $lidar0 -> $lidar1"
  echo "    server rejected undecodable unknown_sensor invalid late: $rej0 -> $rej1"
  local ok=1
  [ "$code" = 0 ] && [ "$puts" -gt 0 ] 2>/dev/null || { echo "    the impostor did not run"; ok=0; }
  [ "$forged" = 0 ] && [ "$forged_status" = 0 ] && [ "$answered" = 0 ] || ok=0
  [ "$genuine_lidar" -gt 0 ] 2>/dev/null && [ "$genuine_tracks" -gt 0 ] || { echo "    the sniffer saw no genuine traffic"; ok=0; }
  # received and processed grow with the genuine lidar; late and invalid must not move. A forged set (seq
  # 2^40 and up) would add about 10^12 to lost; a genuine set lost on a busy host adds one: allowed, shown.
  [ "$(cut -d' ' -f4-5 <<<"$lidar0")" = "$(cut -d' ' -f4-5 <<<"$lidar1")" ] || ok=0
  case "$lidar0 $lidar1" in
    *no-status*) echo "    the server's status did not answer"; fail "$label: no status to compare"; return ;;
  esac
  local lost_grew=$(($(field "$lidar1" 6) - $(field "$lidar0" 6)))
  [ "$lost_grew" -lt 1000 ] || ok=0
  [ "$lost_grew" = 0 ] || echo "    lidar's lost grew by $lost_grew: genuine sets missing from its seq (a forged one would add about 10^12)"
  [ "$rej0" = "$rej1" ] || ok=0
  # The refusals in the router's log, by key, during this probe.
  local set1 tracks1 queryable1
  read -r set1 tracks1 queryable1 <<<"$(refusals "$cn")"
  echo "    router log: $((set1 - set0)) refusals of puts on lidar's key, $((tracks1 - tracks0)) on the tracks keys, $((queryable1 - queryable0)) of the status queryable"
  dc logs --no-color router 2>/dev/null | grep -F "CertCommonName($cn)" | grep 'unauthorized to Put (ingress) on fusion/default/tracks' | tail -1 |
    sed 's/^[^|]*| *//' | cut -c1-200 | sed 's/^/      e.g. /' || true
  [ "$set1" -gt "$set0" ] && [ "$tracks1" -gt "$tracks0" ] && [ "$queryable1" -gt "$queryable0" ] || ok=0
  if [ "$ok" = 1 ]; then
    pass "$label: 0 of $puts forged puts and 0 forged status replies reached anyone, server counters unchanged (lidar lost +$lost_grew), refusals in the router's log"
  else
    fail "$label: something forged got through, a counter moved, or the router logged no refusal (see above)"
  fi
}

section "7b. access control: identities writing where they may not"
acl_probe "acl: impersonation refused (cam1's identity writing lidar's sets and the tracks)" impostor default/cam1
acl_probe "acl: client cannot publish (the checker's identity)" checker checker
