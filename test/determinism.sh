#!/usr/bin/env bash
# Same seed, same result under load: plans PROBLEM alone, then again with two busy
# threads on the planner's CPU (plan --load 2), and fails when the second result.json
# differs from the first apart from time fields (plan --expect says where).
# Usage: determinism.sh CLUTTERTAMP PROBLEM OUTPUT_DIR [TIME_LIMIT]
# TIME_LIMIT (s) replaces the problem's outer limit in both runs (a sanitizer build is
# several times slower; work budgets, not the clock, decide the result).
set -u
cli=$1 problem=$2 out=$3
limit=()
if [ $# -ge 4 ]; then limit=(--time-limit "$4"); fi
rm -rf "$out"
"$cli" plan "$problem" -q --output "$out/alone" "${limit[@]}"
rc=$?
if [ "$rc" -gt 1 ]; then echo "determinism: the first run of $problem exited $rc"; exit 1; fi
reason=$(grep -m1 '"reason"' "$out/alone/result.json")
case "$reason" in
  *"time limit"*) echo "determinism: $problem ended by its time limit, so it proves nothing: $reason"; exit 1 ;;
esac
"$cli" plan "$problem" -q --output "$out/loaded" --load 2 --expect "$out/alone/result.json" "${limit[@]}"
rc=$?
if [ "$rc" -gt 1 ]; then echo "determinism: $problem under load: exit $rc"; exit 1; fi
echo "determinism: $problem: the same result alone and under load"
