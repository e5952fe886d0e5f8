#!/usr/bin/env bash
# Generates the secrets of the secure profile into DIR (default docker/certs/, git-ignored; never commit it),
# for the identities of docker/deployment.txt (docker/render-deployment.py lists them):
#   ca.pem                  a throw-away certificate authority (its key is deleted once every certificate is signed)
#   router.pem, router.key  the router's TLS certificate (SAN: router, router_a, router_b, localhost, 127.0.0.1)
#   <stem>.pem, <stem>.key  one client certificate per identity (mutual TLS), its common name the identity:
#                           agent-<site>-<sensor> (CN <site>/<sensor>), server-<site>-<id> (CN <site>/server/<id>),
#                           client-<name> (CN <name>)
#   users.txt               the router's user:password dictionary (one random password per role: edge-agent,
#                           server, and each client), the second factor beside the certificate
#   zenoh-router.json5      the router's configuration with the access control rendered from deployment.txt
#   zenoh-<stem>.json5      each identity's Zenoh configuration, from docker/zenoh/secure/<role>.json5.in
# Nothing is regenerated while every file is there, none of deployment.txt, the renderer and the templates is
# newer, and the router's certificate is valid for another week.
# Needs openssl; installs it with apt-get when it is missing and this runs as root.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="${1:-$here/certs}"
templates="$here/zenoh/secure"
deployment="$here/deployment.txt"
render=(python3 "$here/render-deployment.py")

# The identities: "<common name> <user> <file stem>" per line.
mapfile -t identities < <("${render[@]}" identities "$deployment")
files=(ca.pem router.pem router.key users.txt zenoh-router.json5)
for line in "${identities[@]}"; do
  read -r _ _ stem <<<"$line"
  files+=("$stem.pem" "$stem.key" "zenoh-$stem.json5")
done

if ! command -v openssl >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "    openssl is missing: installing it with apt-get"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq openssl >/dev/null
  else
    echo "make-certs.sh: openssl is needed to generate the secure profile's certificates; install it" >&2
    exit 1
  fi
fi

complete=1
for f in "${files[@]}"; do [ -s "$out/$f" ] || complete=0; done
# The deployment, its renderer or a template may have changed since the files were made.
for t in "$deployment" "$here/render-deployment.py" "$templates"/*.json5.in; do
  [ "$complete" = 1 ] && [ "$t" -nt "$out/zenoh-router.json5" ] && complete=0
done
if [ "$complete" = 1 ] && openssl x509 -checkend $((7 * 86400)) -noout -in "$out/router.pem" >/dev/null; then
  echo "    present and valid: $out (${#identities[@]} identities of deployment.txt)"
  exit 0
fi

mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Explicit extensions: rustls (Zenoh's TLS) insists on a CA with keyCertSign, a server leaf with a
# matching SAN, and a client leaf for client authentication.
cat >"$work/openssl.cnf" <<'CNF'
[req]
distinguished_name = dn
prompt = no
[dn]
CN = fusion test CA
[v3_ca]
basicConstraints = critical,CA:TRUE
keyUsage = critical,keyCertSign,cRLSign
subjectKeyIdentifier = hash
[v3_router]
basicConstraints = critical,CA:FALSE
keyUsage = critical,digitalSignature
extendedKeyUsage = serverAuth
subjectAltName = DNS:router,DNS:router_a,DNS:router_b,DNS:localhost,IP:127.0.0.1
subjectKeyIdentifier = hash
authorityKeyIdentifier = keyid
[v3_client]
basicConstraints = critical,CA:FALSE
keyUsage = critical,digitalSignature
extendedKeyUsage = clientAuth
subjectKeyIdentifier = hash
authorityKeyIdentifier = keyid
CNF

openssl req -x509 -config "$work/openssl.cnf" -extensions v3_ca -days 365 -nodes \
  -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -keyout "$work/ca.key" -out "$work/ca.pem" 2>/dev/null
sign() { # stem, common name, extensions
  # A "/" in the common name (<site>/<sensor>) is escaped for -subj.
  openssl req -new -config "$work/openssl.cnf" -subj "/CN=${2//\//\\/}" -nodes \
    -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -keyout "$work/$1.key" -out "$work/$1.csr" 2>/dev/null
  openssl x509 -req -in "$work/$1.csr" -CA "$work/ca.pem" -CAkey "$work/ca.key" -set_serial "0x$(openssl rand -hex 8)" \
    -days 365 -extfile "$work/openssl.cnf" -extensions "$3" -out "$work/$1.pem" 2>/dev/null
  openssl verify -CAfile "$work/ca.pem" "$work/$1.pem" >/dev/null
}
sign router router v3_router

# One password per user (a role, or a client), so that one can be changed alone.
: >"$work/users.txt"
declare -A password
for line in "${identities[@]}"; do
  read -r cn user stem <<<"$line"
  sign "$stem" "$cn" v3_client
  if [ -z "${password[$user]:-}" ]; then
    password[$user]="$(openssl rand -hex 24)"
    printf '%s:%s\n' "$user" "${password[$user]}" >>"$work/users.txt"
  fi
  case "$user" in
    edge-agent | server | view) template="$templates/$user.json5.in" ;;
    *) template="$templates/checker.json5.in" ;;
  esac
  sed -e "s|@USER@|$user|" -e "s|@PASSWORD@|${password[$user]}|" -e "s|@STEM@|$stem|g" -e "s|@CN@|$cn|" \
    "$template" >"$work/zenoh-$stem.json5"
done
rm -f "$work/ca.key"
"${render[@]}" acl "$deployment" >"$work/acl.json"
python3 - "$templates/router.json5.in" "$work/acl.json" >"$work/zenoh-router.json5" <<'PY'
import sys
template, acl = (open(p, encoding="utf-8").read() for p in sys.argv[1:3])
indented = acl.strip().replace("\n", "\n  ")
print(template.replace("@USERS_FILE@", "/certs/users.txt").replace("@ACCESS_CONTROL@", indented), end="")
PY

# The containers run as nobody (65534): the files must be readable by it. They are test secrets on a
# developer's or CI machine; a production deployment mounts its own with tighter ownership.
rm -f "$out"/*.pem "$out"/*.key "$out"/zenoh-*.json5
for f in "${files[@]}"; do install -m 0644 "$work/$f" "$out/$f"; done
echo "    generated in $out: CA, router certificate, ${#identities[@]} client certificates of deployment.txt, users.txt, Zenoh configurations"
openssl x509 -noout -subject -enddate -in "$out/router.pem" | sed 's/^/    router certificate /'
openssl x509 -noout -subject -in "$out/agent-default-cam1.pem" 2>/dev/null | sed 's/^/    e.g. agent certificate /' || true
