#!/usr/bin/env bash
# Usage: scripts/check-skips.sh "STAGE..." CTEST_LOG
# Lists every test the ctest run in CTEST_LOG skipped, with the reason tests/expected_skips gives
# for one of the STAGEs (space-separated), and fails when a skip has none: a test that stops
# running unnoticed is a test lost.
set -euo pipefail
stages=" $1 "
log=$2
list="$(dirname "$0")/../tests/expected_skips"
skipped=$(sed -n 's/^[[:space:]]*[0-9][0-9]* - \([^[:space:]]*\).*(Skipped)$/\1/p' "$log")
unexpected=0
count=0
while IFS= read -r name; do
    [ -n "$name" ] || continue
    count=$((count + 1))
    reason=""
    while IFS= read -r line; do
        case "$line" in '#'* | '') continue ;; esac
        read -r line_stage pattern _ <<<"$line"
        [[ "$stages" == *" $line_stage "* ]] || continue
        if grep -Eq -- "$pattern" <<<"$name"; then
            reason=${line#*# }
            break
        fi
    done <"$list"
    if [ -n "$reason" ]; then
        echo "skipped: $name: $reason"
    else
        echo "UNEXPECTED SKIP: $name (not in tests/expected_skips for$stages)"
        unexpected=$((unexpected + 1))
    fi
done <<<"$skipped"
echo "$count tests skipped (stages:$stages), $unexpected of them unexpected"
[ "$unexpected" -eq 0 ]
