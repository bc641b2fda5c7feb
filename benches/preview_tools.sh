#!/usr/bin/env bash
# How fast the preview's 't' (GET /api/raytree) and 'r' (POST /api/render) answer: the Stanford
# bunny at 400x400 with -shadows -bounces 5, the centre pixel's tree and the whole view; medians
# of 5 requests each, timed by curl on loopback.
#   bash benches/preview_tools.sh [SCENE]     (needs target/release/raycast and curl)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
raycast="$here/target/release/raycast"
scene="$(realpath "${1:-$here/../shared/bench/scenes/bunny.txt}")"
work="$(mktemp -d)"
trap 'kill $pid 2>/dev/null || true; rm -rf "$work"' EXIT
(cd "$(dirname "$scene")" && exec "$raycast" -input "$scene" -size 400 400 -output "$work/o.png" \
    -shadows -bounces 5 -gui -port 0 -no-browser > "$work/url.txt" 2> "$work/err.txt") &
pid=$!
for _ in $(seq 1 100); do [[ -s "$work/url.txt" ]] && break; sleep 0.1; done
url="$(head -1 "$work/url.txt")"
base="${url%%/\?*}"
token="${url##*token=}"
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
tree=()
render=()
for _ in 1 2 3 4 5; do
    tree+=("$(curl -s -o /dev/null -w '%{time_total}' "$base/api/raytree?x=200&y=200&token=$token")")
    render+=("$(curl -s -o /dev/null -w '%{time_total}' -X POST "$base/api/render?token=$token")")
done
curl -s -X POST "$base/api/quit?token=$token" || true
echo "scene: $scene at 400x400, -shadows -bounces 5"
echo "t (ray tree of the centre pixel): $(printf '%s\n' "${tree[@]}" | median) s (median of 5)"
echo "r (render of the view, images written): $(printf '%s\n' "${render[@]}" | median) s (median of 5)"
