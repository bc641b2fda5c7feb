#!/usr/bin/env bash
# How long `raycast check` takes over a suite whose every picture fails, against the renderer's
# own time: the target is at most twice the renderer's time plus 10 s.
#   bash benches/check_speed.sh [SUITE] [FAULT]    (defaults: ../shared/conformance pixel_corner)
# Uses target/release/raycast (cargo build --release first). Prints the medians of 5 runs.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
raycast="$here/target/release/raycast"
suite="$(cd "${1:-$here/../shared/conformance}" && pwd)"
fault="${2:-pixel_corner}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
renderer="$work/renderer.sh"
printf '#!/usr/bin/env bash\nexec %s "$@" -fault %s\n' "$raycast" "$fault" > "$renderer"
chmod +x "$renderer"
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
own=()
checked=()
for _ in 1 2 3 4 5; do
    # The renderer alone: every line of the suite, one after another, in a copy of its scenes.
    cp -r "$suite/scenes" "$work/scenes"
    start=$(date +%s%N)
    (cd "$work/scenes" && grep '^raytracer ' "$suite/COMMANDS.txt" | sed 's/->.*//; s/(preview only).*//' \
        | while read -r _ args; do "$renderer" $args >/dev/null 2>&1 || true; done)
    own+=("$(( ($(date +%s%N) - start) / 1000000 ))")
    rm -rf "$work/scenes"
    start=$(date +%s%N)
    "$raycast" check "$suite" --renderer "$renderer" --allow-read "$(dirname "$raycast")" > "$work/out.txt" || true
    checked+=("$(( ($(date +%s%N) - start) / 1000000 ))")
done
echo "renderer alone: $(printf '%s\n' "${own[@]}" | median) ms (median of 5)"
echo "raycast check:  $(printf '%s\n' "${checked[@]}" | median) ms (median of 5)"
echo "failing pictures: $(grep -c '^FAIL' "$work/out.txt"), named $fault first: $(grep -c ": $fault[,:]" "$work/out.txt")"
