#!/usr/bin/env bash
# Builds the Docker images of the deployment (docker/README.md), from a clean clone, without a registry:
#   1. the workspace's static binaries (reused when .ci/run already built them: same target and flags),
#      the router fusion-router among them (a Zenoh session in router mode: no separate zenohd build);
#   2. the secure profile's identities (docker/deployment.txt): a TLS client certificate each, passwords,
#      the router's access control, into docker/certs/ (git-ignored);
#   3. one FROM-scratch image per program: fusion/router, fusion/server, fusion/edge-agent, fusion/checker,
#      fusion/view.
# Every step is skipped when its result is already there, so a second run takes seconds.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
cd "$repo"

TAG="${FUSION_IMAGE_TAG:-latest}"

# The same target and flags as .ci/run: cargo then finds its own build and does nothing.
export CARGO_BUILD_TARGET=x86_64-unknown-linux-gnu
export RUSTFLAGS="-C target-feature=+crt-static"
target_dir="${CARGO_TARGET_DIR:-$repo/target}"
bin_dir="$target_dir/$CARGO_BUILD_TARGET/release"
context="$target_dir/docker-context"

step_began=0
step() {
  step_began=$SECONDS
  printf '\n--- %s\n' "$1"
}
done_step() { printf '    (%d s)\n' "$((SECONDS - step_began))"; }

# ------------------------------------------------------------------ 1. our binaries
step "workspace binaries (static, $bin_dir)"
programs=(fusion-router fusion-server edge-agent fusion-checker fusion-view)
missing=0
for p in "${programs[@]}"; do [ -x "$bin_dir/$p" ] || missing=1; done
if [ "$missing" = 1 ] || [ "${FUSION_REBUILD:-0}" = 1 ]; then
  # Incremental: after .ci/run's build this only links what changed.
  cargo build --release --locked --workspace --bins
else
  echo "    present (FUSION_REBUILD=1 forces cargo build)"
fi
done_step

# ------------------------------------------------------------------ 2. certificates and credentials
step "identities of docker/deployment.txt for the secure profile: certificates, passwords, access control (docker/certs/)"
"$here/make-certs.sh" "$here/certs"
done_step

# ------------------------------------------------------------------ 3. images
step "images FROM scratch (tag $TAG)"
# The build context holds only what the images copy: the binaries and the baked-in configuration.
mkdir -p "$context/bin" "$context/config" "$context/state"
sync_file() { # copies $1 to $2 unless identical (keeps mtimes, so the context stays stable)
  cmp -s "$1" "$2" 2>/dev/null || cp -p "$1" "$2"
}
for p in "${programs[@]}"; do sync_file "$bin_dir/$p" "$context/bin/$p"; done
sync_file "$here/config/fusion.toml" "$context/config/fusion.toml"
for f in "$here"/zenoh/*.json5; do sync_file "$f" "$context/config/$(basename "$f")"; done
sync_file "$here/Dockerfile" "$context/Dockerfile"

# "docker build" pulls nothing here: every stage is FROM scratch (no registry is needed or reachable).
for image in router server edge-agent checker view; do
  # Quiet unless it fails (the legacy builder also warns that it is deprecated).
  if ! log="$(docker build --target "$image" --tag "fusion/$image:$TAG" "$context" 2>&1)"; then
    echo "$log"
    exit 1
  fi
  size="$(docker image inspect --format '{{.Size}}' "fusion/$image:$TAG")"
  printf '    fusion/%-18s %5.1f MB\n' "$image:$TAG" "$(awk "BEGIN { print $size / 1e6 }")"
done
done_step

# ------------------------------------------------------------------ 4. smoke test of the images
step "smoke test: each image starts, and service names resolve in the static binaries"
for image in router server edge-agent checker view; do
  version="$(docker run --rm -e RUST_LOG=error -e NO_COLOR=1 "fusion/$image:$TAG" --version)"
  printf '    fusion/%-18s runs: %s\n' "$image:$TAG" "$version"
done
# A router on a throw-away network, reached by its container name through /etc/hosts + Docker DNS:
# proves that glibc's static getaddrinfo works from scratch images.
net="fusion-build-smoke-$$"
docker network create "$net" >/dev/null
cleanup_smoke() {
  docker rm -f "$net-router" >/dev/null 2>&1 || true
  docker network rm "$net" >/dev/null 2>&1 || true
}
trap cleanup_smoke EXIT
docker run -d --name "$net-router" --network "$net" --network-alias smoke-router --init \
  "fusion/router:$TAG" --config /etc/fusion/zenoh/router.json5 >/dev/null
resolved=0
for _ in $(seq 1 20); do
  # `status` fails (no fusion server) but only after the session opened, which needs the name resolved.
  out="$(docker run --rm --network "$net" "fusion/checker:$TAG" --connect tcp/smoke-router:7447 status 2>&1 || true)"
  if grep -q "no reply" <<<"$out"; then
    resolved=1
    break
  fi
  sleep 0.5
done
if [ "$resolved" = 1 ]; then
  echo "    checker reached the router as tcp/smoke-router:7447 (service-name resolution works)"
else
  echo "    FAIL: the checker could not reach tcp/smoke-router:7447:"
  echo "$out" | sed 's/^/      /'
  exit 1
fi
cleanup_smoke
trap - EXIT
done_step
echo
echo "build.sh: done in $SECONDS s"
