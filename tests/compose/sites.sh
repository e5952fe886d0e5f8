# The many-sites check, sourced by tests/compose/run.sh (its helpers): docker-compose.sites.yml runs the sites
# room_a and room_b, each with three agents and a server on its own router, router_a connected to router_b.
#   sites: mesh   a client of either router gets both sites' tracks and status (fusion/*/tracks,
#                 fusion/*/status); after `restart` of either router, a client of the other one gets both
#                 again within 5 s of the restart's end (container start of the checker included).

start_project "fusionsites$$" "${sites[@]}"
SERVICES=(router_a router_b server_a server_b a_cam1 a_mics_n a_lidar b_cam1 b_mics_n b_lidar)
section "9. many sites: room_a and room_b over a mesh of two routers"
both_sites() { # checker service, timeout: the sites answer ("site:tracks:alive ..."); fails when one is missing
  local out code=0
  out="$(dc run --rm -T "$1" sites --expect room_a,room_b --timeout "$2" 2>/dev/null)" || code=$?
  inspect sites <<<"$out" 2>/dev/null || echo "no answer"
  return "$code"
}
START=$(($(date +%s) + 3))
export START
echo "  project $project, START $START, SEED $SEED"
if out="$(dc up -d 2>&1)"; then
  if answer="$(both_sites checker_a 60)"; then
    pass "sites: startup: both sites answered on router_a ($answer)"
  else
    fail "sites: startup: not both sites on router_a within 60 s ($answer)"
  fi
  record_started
  a_view="$(both_sites checker_a 5)" && b_view="$(both_sites checker_b 5)" && mesh=1 || mesh=0
  echo "    site:tracks:live sensors from router_a: $a_view; from router_b: ${b_view:-}"
  if [ "$mesh" = 1 ]; then
    pass "sites: mesh: tracks and status of both sites answered on either router"
  else
    fail "sites: mesh: a router does not answer for both sites"
  fi
  for pair in "router_b checker_a" "router_a checker_b"; do
    read -r restarted client <<<"$pair"
    dc restart "$restarted" >/dev/null 2>&1
    t0="$(now)"
    if answer="$(both_sites "$client" 15)"; then
      healed="$(elapsed "$t0")"
      if le "$healed" 5; then
        pass "sites: mesh healed $healed s after restarting $restarted ($client: $answer)"
      else
        fail "sites: mesh took $healed s (> 5 s) to heal after restarting $restarted"
      fi
    else
      fail "sites: mesh not healed 15 s after restarting $restarted ($answer)"
    fi
  done
  check_no_restarts "sites" router_a router_b
else
  echo "$out"
  fail "sites: compose up failed"
fi
section "many sites: down"
down_project
