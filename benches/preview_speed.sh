#!/usr/bin/env bash
# The preview's speed in headless Chromium (WebGL through SwiftShader): the 69k-triangle Stanford
# bunny at 400x400, a left drag of 120 steps of 2 pixels; prints the time to the first frame
# after the page's load starts (the browser's own start not counted) and the frames per second
# (frames drawn, each a changed canvas, over the drag's wall time). Medians of 5 runs.
#   bash benches/preview_speed.sh [SCENE] [SIZE]
# Needs target/release/raycast (cargo build --release), chromium and
# `npm ci --prefix tests/preview`.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
raycast="$here/target/release/raycast"
scene="$(realpath "${1:-$here/../shared/bench/scenes/bunny.txt}")"
size="${2:-400}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
first=()
fps=()
for _ in 1 2 3 4 5; do
    (cd "$(dirname "$scene")" && "$raycast" -input "$scene" -size "$size" "$size" -output "$work/o.png" \
        -gui -port 0 -no-browser > "$work/url.txt" 2> "$work/err.txt") &
    for _ in $(seq 1 100); do [[ -s "$work/url.txt" ]] && break; sleep 0.1; done
    url="$(head -1 "$work/url.txt")"
    printf '{"url": "%s", "steps": [{"fps": [120, 2]}, {"key": "q"}]}' "$url" > "$work/script.json"
    report="$(cd "$here/tests/preview" && node drive.mjs "$work/script.json")"
    wait
    first+=("$(echo "$report" | sed 's/.*"first_frame_ms":\([0-9]*\).*/\1/')")
    fps+=("$(echo "$report" | sed 's/.*"fps":\([0-9.]*\).*/\1/')")
    rm -f "$work/url.txt"
done
echo "scene: $scene at ${size}x${size}"
echo "first frame: $(printf '%s\n' "${first[@]}" | median) ms after the page's load began (median of 5)"
echo "frames/s over 120 drag steps: $(printf '%s\n' "${fps[@]}" | median) (median of 5)"
