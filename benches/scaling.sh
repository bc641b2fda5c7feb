#!/usr/bin/env bash
# Per-phase times of one scene at 1..N threads, for the scaling table of docs/performance.md:
# parse and load, BVH build, render and image write, each the median of REPS runs (raycast's own
# -stats timings), and the render's speed-up over one thread.
#
#   cargo build --release && bash benches/scaling.sh [SCENE] [SIZE] [MAX_THREADS] [REPS]
#
# Defaults: ../shared/bench/scenes/bunny.txt, 1024, every core, 5. On a many-core machine, copy
# target/release/raycast and the scene (with its mesh) there and run the same.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
raycast="${RAYCAST:-$here/target/release/raycast}"
scene="${1:-$here/../shared/bench/scenes/bunny.txt}"
size="${2:-1024}"
max="${3:-$(nproc)}"
reps="${4:-5}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

printf '%-8s %12s %12s %12s %12s %10s\n' threads "parse (ms)" "build (ms)" "render (ms)" "write (ms)" speed-up
one=""
for ((threads = 1; threads <= max; threads++)); do
    : >"$out/parse"; : >"$out/build"; : >"$out/render"; : >"$out/write"
    for ((rep = 0; rep < reps; rep++)); do
        "$raycast" -input "$scene" -size "$size" "$size" -output "$out/image.ppm" \
            -threads "$threads" -stats 2>"$out/stats" >/dev/null
        awk '/parse and load/ { print $5 > "'"$out/parse"'.tmp" }
             /build BVH/      { print $4 > "'"$out/build"'.tmp" }
             /render   /      { print $3 > "'"$out/render"'.tmp" }
             /write images/   { print $4 > "'"$out/write"'.tmp" }' "$out/stats"
        for phase in parse build render write; do cat "$out/$phase.tmp" >>"$out/$phase"; done
    done
    parse=$(median <"$out/parse"); build=$(median <"$out/build")
    render=$(median <"$out/render"); write=$(median <"$out/write")
    [[ -z $one ]] && one=$render
    printf '%-8s %12s %12s %12s %12s %9.2fx\n' "$threads" "$parse" "$build" "$render" "$write" \
        "$(awk "BEGIN { print $one / $render }")"
done
