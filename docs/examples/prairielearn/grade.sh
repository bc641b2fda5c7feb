#!/usr/bin/env bash
# PrairieLearn's external grader entry point (the question's info.json names it, see
# docs/grading.md): the student's files are in $GRADE_ROOT/student, the question's in
# $GRADE_ROOT/tests (the suite in tests/suite), and $GRADE_ROOT/results/results.json is read
# back. GRADE_ROOT is /grade in PrairieLearn's container; RAYCAST names the program.
set -uo pipefail
root="${GRADE_ROOT:-/grade}"
raycast="${RAYCAST:-raycast}"
cd "$root/student" || exit 1
mkdir -p "$root/results"
if [[ -f Makefile ]]; then
    if ! make > "$root/build.log" 2>&1; then
        # The submission does not build: nothing is graded. Tell the student why (the build's
        # last 100 lines) and score nothing.
        printf '{"gradable": true, "score": 0, "message": %s}\n' \
            "$(python3 -c 'import json,sys; lines=open(sys.argv[1], errors="replace").read().splitlines(True)[-100:]; print(json.dumps("The build failed: make ended with an error, so nothing was graded. The last 100 lines of its output:\n" + "".join(lines)))' "$root/build.log")" \
            > "$root/results/results.json"
        exit 0
    fi
fi
# --timeout: a line that hangs is ended after 60 seconds; --budget: all the lines together get
# 600 seconds (keep it under the question's grader timeout, with a minute for the report).
"$raycast" check "$root/tests/suite" --renderer ./raytracer --report "$root/report" \
    --timeout 60 --budget 600 > "$root/check.log" 2>&1
if [[ -f "$root/report/prairielearn.json" ]]; then
    cp "$root/report/prairielearn.json" "$root/results/results.json"
else
    printf '{"gradable": false, "message": %s}\n' \
        "$(python3 -c 'import json,sys; print(json.dumps(open(sys.argv[1]).read()))' "$root/check.log")" \
        > "$root/results/results.json"
fi
