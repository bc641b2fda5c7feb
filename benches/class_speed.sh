#!/usr/bin/env bash
# How long `raycast check --class` takes to grade a class of synthetic submissions: each a
# folder with a Makefile that builds `raytracer`, a script around raycast with one of the
# library's faults planted (every fifth student has none), graded over a suite with the report
# and its four formats written.
#   bash benches/class_speed.sh [STUDENTS] [SUITE]   (defaults: 100 ../shared/conformance)
# Uses target/release/raycast (cargo build --release first); RAYCAST=path picks another.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
raycast="${RAYCAST:-$here/target/release/raycast}"
students="${1:-100}"
suite="$(cd "${2:-$here/../shared/conformance}" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
chmod 755 "$work"
faults=(none pixel_corner ambient_missing channel_swap flip_vertical shade_back_ignored
        cosine_twice field_of_view t_limit normals_signed)
for ((k = 0; k < students; k++)); do
    folder="$work/roster/student$(printf %03d "$k")"
    mkdir -p "$folder"
    fault="${faults[k % ${#faults[@]}]}"
    if [[ $fault == none ]]; then planted=""; else planted="-fault $fault"; fi
    printf '#!/bin/sh\nexec %s %s "$@"\n' "$raycast" "$planted" > "$folder/raytracer.in"
    printf 'raytracer: raytracer.in\n\tcp raytracer.in raytracer\n\tchmod +x raytracer\n' > "$folder/Makefile"
done
chmod -R a+rX "$work"
start=$(date +%s%N)
"$raycast" check "$suite" --class "$work/roster" --build make --renderer ./raytracer \
    --allow-read "$(dirname "$raycast")" --report "$work/report" > "$work/table.txt"
elapsed=$(( ($(date +%s%N) - start) / 1000000 ))
rows=$(grep -c '^student[0-9]' "$work/table.txt")
for format in gradescope.json prairielearn.json junit.xml github-classroom.json; do
    found=$(ls "$work"/report/student*/"$format" | wc -l)
    [[ $found -eq $students ]] || { echo "only $found of $students $format" >&2; exit 1; }
done
[[ -s "$work/report/class.csv" && -s "$work/report/class.html" ]]
echo "$students students ($rows rows), $(grep -c '^raytracer ' "$suite/COMMANDS.txt") lines each: ${elapsed} ms in all, $((elapsed / students)) ms a student (nproc $(nproc))"
