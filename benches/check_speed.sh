#!/usr/bin/env bash
# How long `raycast check` takes against the renderer's own time over the same lines.
#
#   bash benches/check_speed.sh [--step N] [--students N] [--faults "a b c,d"] [--no-class]
#
# 1. For each suite (the course's conformance suite and the later assignments) and each planted
#    fault (a pair is two faults joined by a comma): the renderer alone over every line, one
#    after another, in a copy of the suite's scenes; then check over the suite, the lines run one
#    at a time (--jobs 1, as the renderer alone was), twice: with the cache empty (raycast
#    renders the references the suite lacks, the seeded renders of the failing pictures drawn
#    by chance, and every fault), and with the suite's references kept (as after any earlier
#    check of the suite on the machine, seeded renders included; the faults' renders are
#    not). Target: check at most 2 x the renderer's time + 10 s.
# 2. A class of N submissions (default 20) with mixed faults (every fifth has none): the sum of
#    their renderers' own times (each fault's time measured once above, times its students),
#    check --class with the cache empty, then again with it warm. Targets: at most 1.3 x the
#    renderers' times + one simulation of the suite (check's time for one student, cold), and
#    warm at most 1.1 x the renderers' times.
#
# --step N keeps every Nth line of each suite (a shorter run; say so with its figures).
# Uses target/release/raycast (cargo build --release first); RAYCAST=path picks another.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
raycast="${RAYCAST:-$here/target/release/raycast}"
step=1
students=20
class=yes
faults=(shadow_acne pixel_corner ambient_missing refraction_index filter_radius
        shadow_acne,ambient_missing)
while [[ $# -gt 0 ]]; do
    case "$1" in
        --step) step="$2"; shift 2 ;;
        --students) students="$2"; shift 2 ;;
        --faults) read -r -a faults <<< "$2"; shift 2 ;;
        --no-class) class=no; shift ;;
        *) echo "check_speed.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
chmod 755 "$work"
now() { date +%s%N; }
seconds() { awk -v ns="$1" 'BEGIN { printf "%.1f", ns / 1e9 }'; }

# A suite of every $step-th line of $1, in $work/suites/NAME.
subsuite() {
    local from name
    from="$(cd "$1" && pwd)"
    name="$(basename "$from")"
    mkdir -p "$work/suites/$name"
    ln -s "$from/scenes" "$work/suites/$name/scenes"
    [[ -d "$from/reference" ]] && ln -s "$from/reference" "$work/suites/$name/reference"
    grep '^raytracer ' "$from/COMMANDS.txt" | awk -v step="$step" '(NR - 1) % step == 0' \
        > "$work/suites/$name/COMMANDS.txt"
    echo "$work/suites/$name"
}

# A renderer: raycast with the faults $1 planted ("none": raycast itself).
renderer() {
    local path="$work/renderers/${1//,/+}.sh"
    mkdir -p "$work/renderers"
    if [[ $1 == none ]]; then
        printf '#!/bin/sh\nexec %s "$@"\n' "$raycast" > "$path"
    elif [[ $1 == reseeded ]]; then
        printf '#!/bin/sh\nexec %s "$@" -seed 1\n' "$raycast" > "$path"
    else
        printf '#!/bin/sh\nexec %s "$@" -fault %s\n' "$raycast" "$1" > "$path"
    fi
    chmod 755 "$path"
    echo "$path"
}

# The renderer $2 alone over every line of suite $1, in a copy of its scenes: nanoseconds.
own_time() {
    local copy="$work/own"
    rm -rf "$copy"
    cp -rL "$1/scenes" "$copy"
    local start
    start=$(now)
    (cd "$copy" && sed 's/->.*//; s/(preview only).*//' "$1/COMMANDS.txt" \
        | while read -r _ args; do "$2" $args > /dev/null 2>&1 || true; done)
    echo $(( $(now) - start ))
    rm -rf "$copy"
}

declare -A own
# check of suite $1 with renderer $2 and the cache $3: nanoseconds; its output in $work/out.txt.
# A check that could not grade (exit 2: a usage or suite problem) ends the bench with its words.
check_time() {
    local start status=0
    start=$(now)
    RAYCAST_CACHE_DIR="$3" "$raycast" check "$1" --renderer "$2" --jobs 1 \
        --allow-read "$(dirname "$raycast")" > "$work/out.txt" 2> "$work/err.txt" || status=$?
    if (( status > 1 )); then
        echo "check_speed.sh: check exited $status: $(tail -3 "$work/err.txt")" >&2
        exit 1
    fi
    echo $(( $(now) - start ))
}
verdict() {
    awk -v c="$1" -v o="$2" 'BEGIN { printf "%.2f %s", c / o, (c <= 2 * o + 10e9) ? "met" : "MISSED" }'
}
printf '%-18s %-28s %8s %15s %22s %s\n' suite fault "own (s)" "check, cold (s)" \
    "check, refs kept (s)" failing
for suite in "$here/../shared/conformance" "$here/../shared/later-assignments"; do
    suite="$(subsuite "$suite")"
    name="$(basename "$suite")"
    # The suite's references, as any earlier check of it on this machine keeps them: with
    # another seed, so that the lines drawn by chance keep their seeded renders too (raycast's
    # own pictures pass without them).
    check_time "$suite" "$(renderer reseeded)" "$work/references-$name" > /dev/null
    for fault in "${faults[@]}"; do
        r="$(renderer "$fault")"
        alone=$(own_time "$suite" "$r")
        own["$name/$fault"]=$alone
        cold=$(check_time "$suite" "$r" "$work/cache-$name-${fault//,/+}")
        rm -rf "$work/kept"
        # (A suite whose references are all the staff's keeps none.)
        mkdir -p "$work/references-$name"
        cp -r "$work/references-$name" "$work/kept"
        kept=$(check_time "$suite" "$r" "$work/kept")
        failing=$(grep -c '^FAIL' "$work/out.txt" || true)
        printf '%-18s %-28s %8s %6s %8s %6s %15s %s\n' "$name" "$fault" "$(seconds "$alone")" \
            "$(seconds "$cold")" "$(verdict "$cold" "$alone")" "$(seconds "$kept")" \
            "$(verdict "$kept" "$alone")" "$failing"
    done
done

[[ $class == yes ]] || exit 0
suite="$work/suites/later-assignments"
mixed=(none "${faults[@]}")
mkdir -p "$work/roster"
renderers_total=0
for ((k = 0; k < students; k++)); do
    folder="$work/roster/student$(printf %03d "$k")"
    mkdir -p "$folder"
    if (( k % 5 == 0 )); then fault=none; else fault="${faults[k % ${#faults[@]}]}"; fi
    if [[ -z ${own["later-assignments/$fault"]:-} ]]; then
        own["later-assignments/$fault"]=$(own_time "$suite" "$(renderer "$fault")")
    fi
    renderers_total=$(( renderers_total + ${own["later-assignments/$fault"]} ))
    cp "$(renderer "$fault")" "$folder/raytracer"
done
chmod -R a+rX "$work"
# One simulation of the suite: check's time for one student with every picture failing.
single=$(( ${own["later-assignments/pixel_corner"]:-0} ))
start=$(now)
RAYCAST_CACHE_DIR="$work/cache-pixel_corner" "$raycast" check "$suite" --jobs 1 \
    --renderer "$(renderer pixel_corner)" --allow-read "$(dirname "$raycast")" > /dev/null 2>&1 || true
simulation=$(( $(now) - start - single ))
for run in cold warm; do
    start=$(now)
    RAYCAST_CACHE_DIR="$work/cache-class" "$raycast" check "$suite" --class "$work/roster" \
        --renderer ./raytracer --jobs 1 --allow-read "$(dirname "$raycast")" \
        --report "$work/report-$run" > /dev/null 2>&1 || true
    took=$(( $(now) - start ))
    ratio=$(awk -v c="$took" -v o="$renderers_total" 'BEGIN { printf "%.2f", c / o }')
    if [[ $run == cold ]]; then
        met=$(awk -v c="$took" -v o="$renderers_total" -v s="$simulation" \
            'BEGIN { print (c <= 1.3 * o + s) ? "met" : "MISSED" }')
    else
        met=$(awk -v c="$took" -v o="$renderers_total" 'BEGIN { print (c <= 1.1 * o) ? "met" : "MISSED" }')
    fi
    echo "class of $students, cache $run: renderers $(seconds "$renderers_total") s, check $(seconds "$took") s, ratio $ratio ($met; one simulation of the suite: $(seconds "$simulation") s)"
done
echo "(every ${step}th line of each suite; nproc $(nproc); $("$raycast" -version 2>/dev/null | head -1))"
