#!/usr/bin/env bash
# The whole test suite: `cargo test --workspace` (extra arguments are passed
# on), the Python package's pytest suite (scripts/python_test.sh), then one
# summary line over all of it, so that the last line on screen says whether
# everything passed (a group is a test binary, a crate's doc tests, or the
# pytest run):
#   all tests: 318 passed, 0 failed, 3 ignored (20 test groups, 412 s)
# `bash scripts/test.sh --summarize LOG` prints the summary of a saved log.
set -uo pipefail
cd "$(dirname "$0")/.."

summarize() {
    awk -v seconds="${2:-}" '
        # pytest -q ends with "3 failed, 40 passed, 1 skipped in 4.51s".
        /^(=+ )?[0-9]+ (passed|failed|skipped|error)/ && / in [0-9.]+s/ {
            binaries++
            for (i = 1; i <= NF; i++) {
                if ($(i + 1) ~ /^passed/) passed += $i
                if ($(i + 1) ~ /^(failed|error)/) failed += $i
                if ($(i + 1) ~ /^skipped/) ignored += $i
            }
        }
        /^test result:/ {
            binaries++
            for (i = 1; i <= NF; i++) {
                if ($(i + 1) ~ /^passed/) passed += $i
                if ($(i + 1) ~ /^failed/) failed += $i
                if ($(i + 1) ~ /^ignored/) ignored += $i
            }
        }
        END {
            if (binaries == 0) { print "all tests: no test results found"; exit 1 }
            line = sprintf("all tests: %d passed, %d failed, %d ignored (%d test groups", passed, failed, ignored, binaries)
            if (seconds != "") line = line ", " seconds " s"
            print line ")"
            if (failed > 0) exit 1
        }' "$1"
}

if [ "${1:-}" = "--summarize" ]; then
    summarize "$2"
    exit
fi

log=$(mktemp)
trap 'rm -f "$log"' EXIT
start=$(date +%s)
cargo test --workspace "$@" 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
# The binary cargo test built for the integration tests (tests/flexbody).
FLEXBODY_BIN="$PWD/target/debug/flexbody" bash scripts/python_test.sh 2>&1 | tee -a "$log"
python_status=${PIPESTATUS[0]}
[ "$python_status" = 0 ] || status=${status/#0/1}
echo
summarize "$log" "$(($(date +%s) - start))" || status=${status/#0/1}
exit "$status"
