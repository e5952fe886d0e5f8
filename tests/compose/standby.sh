# The hot-standby check, sourced by tests/compose/run.sh (its helpers): docker-compose.standby.yml runs two
# servers of role auto (instances a and b, services server and server_b) beside the plain profile.
#   standby: takeover   `docker kill` the active server: tracks resume within 2 s (the longest silence a
#                       subscriber saw), the same people keep the same track ids, the new active lost no set
#                       (the sum of its sensors' `lost` counters did not grow), exactly one server is active;
#                       the killed one, started again, comes back as standby. Twice: the servers started
#                       together, then the standby joined a running active server (the one started again).

start_project "fusionstandby$$" "${standby[@]}"
SERVICES=(router server server_b "${SENSORS[@]}")
section "8. hot standby: two servers of role auto"
service_of_instance() { if [ "$1" = a ]; then echo server; else echo server_b; fi; }
# "role lost" of one instance ("down 0" when it does not answer).
instance_role() {
  local out
  out="$(checker_json status --instance "$1")" || { echo "down 0"; return 0; }
  inspect role <<<"$out" || echo "down 0"
}
# Waits up to $2 s until the roles of a and b are "$1" (e.g. "active standby"); prints the last roles seen.
wait_roles() {
  local want="$1" timeout="$2" t0 ra rb
  t0="$(now)"
  while :; do
    read -r ra _ <<<"$(instance_role a)"
    read -r rb _ <<<"$(instance_role b)"
    if [[ "$want" == *"$ra $rb"* ]] || ! le "$(elapsed "$t0")" "$timeout"; then
      echo "$ra $rb"
      [[ "$want" == *"$ra $rb"* ]]
      return
    fi
    sleep 0.5
  done
}

# One takeover: the active server is killed while a subscriber follows the tracks; then it is started again.
takeover() { # label
  local roles active standby_id active_service lost_before before after gaps gaps_pid sets max_gap
  local took_over role_new lost_after role_old compared ids_kept want_roles
  roles="$(wait_roles "active standby|standby active" 20)" || true
  if [ "${roles% *}" = active ]; then active=a standby_id=b; else active=b standby_id=a; fi
  active_service="$(service_of_instance "$active")"
  read -r _ lost_before <<<"$(instance_role "$standby_id")"
  before="$(mktemp)"
  after="$(mktemp)"
  gaps="$(mktemp)"
  checker_json ids --duration 3 >"$before" || true
  checker_json gaps --duration 8 >"$gaps" &
  gaps_pid=$!
  sleep 2
  took_over="$(dc logs --no-color "$(service_of_instance "$standby_id")" 2>/dev/null | grep -c 'taking over as the active server' || true)"
  docker kill "$(container_of "$active_service")" >/dev/null
  echo "    killed $active_service (instance $active, active) at t = $(($(date +%s) - START)) s"
  wait "$gaps_pid" || true
  read -r sets max_gap <<<"$(inspect gaps <"$gaps" 2>/dev/null || echo "0 na")"
  took_over=$(($(dc logs --no-color "$(service_of_instance "$standby_id")" 2>/dev/null | grep -c 'taking over as the active server' || true) - took_over))
  checker_json ids --duration 3 >"$after" || true
  read -r role_new lost_after <<<"$(instance_role "$standby_id")"
  read -r role_old _ <<<"$(instance_role "$active")"
  echo "    subscriber over 8 s around the kill: $sets track sets, longest silence $max_gap s"
  echo "    instance $standby_id: role $role_new, its sensors' lost $lost_before -> $lost_after; 'taking over' logged $took_over times; instance $active: $role_old"
  compared="$(inspect ids-compare "$before" "$after")" && ids_kept=1 || ids_kept=0
  sed 's/^/    /' <<<"$compared"
  rm -f "$before" "$after" "$gaps"
  if [ "$sets" -gt 0 ] 2>/dev/null && le "$max_gap" 2 && [ "$role_new" = active ] && [ "$role_old" = down ] &&
    [ "$ids_kept" = 1 ] && [ "$lost_after" = "$lost_before" ] && [ "$took_over" -gt 0 ]; then
    pass "$1: tracks resumed after a silence of $max_gap s, $(tail -1 <<<"$compared"), lost $lost_before -> $lost_after, one server active ($standby_id)"
  else
    fail "$1: silence ${max_gap} s (<= 2), roles $standby_id=$role_new $active=$role_old, lost $lost_before -> $lost_after, $(tail -1 <<<"$compared"), 'taking over' logged $took_over times"
  fi
  dc start "$active_service" >/dev/null 2>&1
  if [ "$active" = a ]; then want_roles="standby active"; else want_roles="active standby"; fi
  if roles="$(wait_roles "$want_roles" 20)"; then
    pass "$1: the killed server came back as standby ($active: standby, $standby_id: active)"
  else
    fail "$1: after starting $active_service again the roles a, b are '$roles', not '$want_roles'"
  fi
}

if bring_up "standby startup"; then
  if roles="$(wait_roles "active standby|standby active" 20)"; then
    pass "standby: one active and one standby server (a: ${roles% *}, b: ${roles#* })"
  else
    fail "standby: roles a, b are '$roles', not one active and one standby (does this server build know [server] role?)"
  fi
  takeover "standby: takeover (both servers started together)"
  # The server started again joined a running active server (and took its state): kill the active now.
  sleep 3
  takeover "standby: takeover (the standby joined later)"
fi
section "hot standby: down"
down_project
