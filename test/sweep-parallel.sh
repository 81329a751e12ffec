#!/usr/bin/env bash
# The GNU parallel recipe of docs/commands.md, checked: a small `bench retrieval` sweep
# as 4 shards run by `parallel -j 2`, merged, against the same sweep run unsharded, run
# by run (all but the times).
#   sweep-parallel.sh CLUTTERTAMP WORKDIR
set -euo pipefail
cli=$1
work=$2
rm -rf "$work" && mkdir -p "$work/out"
sweep=(--sizes 12 --scenes 1 --runs 2 --planner retrieval_graph --time-limit 600)
parallel -j 2 --halt now,fail=1 "$cli" bench retrieval -q "${sweep[@]}" --shard {}/4 --records "$work/out/shard-{}.jsonl" ::: 0 1 2 3
"$cli" bench merge -q "$work"/out/shard-*.jsonl --csv "$work/merged.csv"
"$cli" bench retrieval -q "${sweep[@]}" --csv "$work/whole.csv"
# Every column but the three times (time_s, task_s, motion_s).
diff <(cut -d, -f1-6,10- "$work/whole.csv") <(cut -d, -f1-6,10- "$work/merged.csv")
echo "sweep-parallel: 4 shards by GNU parallel merged are the unsharded run, run by run"
