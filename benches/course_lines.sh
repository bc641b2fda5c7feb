#!/usr/bin/env bash
# Runs every command line of the course's assignments 3 to 7 (../shared/later-assignments/
# COMMANDS.txt, 168 lines) with the release build, one after another, images into a scratch
# folder, and prints the total wall time and the five slowest lines.
#
#   cargo build --release && bash benches/course_lines.sh [THREADS]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
raycast="$here/target/release/raycast"
data="${RAYCAST_LATER_DIR:-$here/../shared/later-assignments}"
threads="${1:-}"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
cd "$data/scenes"
times="$scratch/times.txt"
total_start=$(date +%s%N)
count=0
while read -r line; do
    command="${line%%->*}"
    command="${command%%(preview only)*}"
    read -r -a args <<<"${command#raytracer }"
    for i in "${!args[@]}"; do
        case "${args[$i]}" in
        -output | -render_samples | -render_filter) args[i + 1]="$scratch/${args[i + 1]}" ;;
        esac
    done
    if [[ -n $threads ]]; then args+=(-threads "$threads"); fi
    start=$(date +%s%N)
    "$raycast" "${args[@]}" >/dev/null 2>"$scratch/stderr" || {
        echo "failed: $command" >&2
        cat "$scratch/stderr" >&2
        exit 1
    }
    end=$(date +%s%N)
    echo "$(((end - start) / 1000000)) ms ${command}" >>"$times"
    count=$((count + 1))
done < <(grep '^raytracer ' "$data/COMMANDS.txt")
total_end=$(date +%s%N)
echo "$count command lines in $(((total_end - total_start) / 1000000)) ms"
echo "slowest:"
sort -rn "$times" | head -5
