#!/usr/bin/env bash
# Generates the secrets of the secure profile into DIR (default docker/certs/, git-ignored; never commit it):
#   ca.pem                  a throw-away certificate authority (its key is deleted once the router's cert is signed)
#   router.pem, router.key  the router's TLS certificate (SAN: router, localhost, 127.0.0.1) and key
#   users.txt               the router's user:password dictionary (one random password per role)
#   zenoh-<role>.json5      the Zenoh configuration of each role, from docker/zenoh/secure/<role>.json5.in,
#                           with its credentials filled in (router, server, edge-agent, checker)
# Nothing is regenerated while every file is there and the certificate is valid for another week.
# Needs openssl; installs it with apt-get when it is missing and this runs as root.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="${1:-$here/certs}"
templates="$here/zenoh/secure"
roles=(server edge-agent checker)
files=(ca.pem router.pem router.key users.txt zenoh-router.json5)
for role in "${roles[@]}"; do files+=("zenoh-$role.json5"); done

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
# The templates may have changed since the files were made.
for t in "$templates"/*.json5.in; do
  [ "$complete" = 1 ] && [ "$t" -nt "$out/zenoh-$(basename "$t" .json5.in).json5" ] && complete=0
done
if [ "$complete" = 1 ] && openssl x509 -checkend $((7 * 86400)) -noout -in "$out/router.pem" >/dev/null; then
  echo "    present and valid: $out"
  exit 0
fi

mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Explicit extensions: rustls (Zenoh's TLS) insists on a CA with keyCertSign and a leaf with a matching SAN.
cat >"$work/openssl.cnf" <<'EOF'
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
subjectAltName = DNS:router,DNS:localhost,IP:127.0.0.1
subjectKeyIdentifier = hash
authorityKeyIdentifier = keyid
EOF

openssl req -x509 -config "$work/openssl.cnf" -extensions v3_ca -days 365 -nodes \
  -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -keyout "$work/ca.key" -out "$work/ca.pem" 2>/dev/null
openssl req -new -config "$work/openssl.cnf" -subj "/CN=router" -nodes \
  -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -keyout "$work/router.key" -out "$work/router.csr" 2>/dev/null
openssl x509 -req -in "$work/router.csr" -CA "$work/ca.pem" -CAkey "$work/ca.key" -set_serial "0x$(openssl rand -hex 8)" \
  -days 365 -extfile "$work/openssl.cnf" -extensions v3_router -out "$work/router.pem" 2>/dev/null
openssl verify -CAfile "$work/ca.pem" "$work/router.pem" >/dev/null

# One user per role, so that a role's password can be changed alone.
: >"$work/users.txt"
declare -A password
for role in "${roles[@]}"; do
  password[$role]="$(openssl rand -hex 24)"
  printf '%s:%s\n' "$role" "${password[$role]}" >>"$work/users.txt"
done
sed "s|@USERS_FILE@|/certs/users.txt|" "$templates/router.json5.in" >"$work/zenoh-router.json5"
for role in "${roles[@]}"; do
  sed -e "s|@USER@|$role|" -e "s|@PASSWORD@|${password[$role]}|" \
    "$templates/$role.json5.in" >"$work/zenoh-$role.json5"
done

# The containers run as nobody (65534): the files must be readable by it. They are test secrets on a
# developer's or CI machine; a production deployment mounts its own with tighter ownership.
for f in "${files[@]}"; do install -m 0644 "$work/$f" "$out/$f"; done
echo "    generated in $out: ${files[*]}"
openssl x509 -noout -subject -enddate -in "$out/router.pem" | sed 's/^/    router certificate /'
