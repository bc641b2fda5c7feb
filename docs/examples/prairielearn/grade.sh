#!/usr/bin/env bash
# PrairieLearn's external grader entry point (the question's info.json names it, see
# docs/grading.md): the student's files are in $GRADE_ROOT/student, the question's in
# $GRADE_ROOT/tests (the suite in tests/suite), and $GRADE_ROOT/results/results.json is read
# back. GRADE_ROOT is /grade in PrairieLearn's container; RAYCAST names the program.
set -uo pipefail
root="${GRADE_ROOT:-/grade}"
raycast="${RAYCAST:-raycast}"
cd "$root/student" || exit 1
if [[ -f Makefile ]]; then
    make > "$root/build.log" 2>&1 || true
fi
"$raycast" check "$root/tests/suite" --renderer ./raytracer --report "$root/report" \
    > "$root/check.log" 2>&1
mkdir -p "$root/results"
if [[ -f "$root/report/prairielearn.json" ]]; then
    cp "$root/report/prairielearn.json" "$root/results/results.json"
else
    printf '{"gradable": false, "message": %s}\n' \
        "$(python3 -c 'import json,sys; print(json.dumps(open(sys.argv[1]).read()))' "$root/check.log")" \
        > "$root/results/results.json"
fi
