#!/usr/bin/env bash
# The sharding recipe of validate/cli/README.md, run as a cluster would run it
# (validate/cli/warpcheck_shard.sh with each engine's own variable): a partial
# run as a Slurm array that lost a task, --missing-shards naming what is
# missing, the missing shard run again as a Kubernetes indexed pod, one as a
# CI matrix entry, and the merge of what came back, which is the unsharded
# run row for row.
# Usage: run_recipe.sh VALIDATE SHARD_SCRIPT WORK_DIR
set -euo pipefail
validate=$1
script=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
fail() { echo "shard recipe: $*"; exit 1; }
# Nine jobs, three of them statistical (judged at the whole run's level, so a
# shard's verdicts depend on the others'): 0.4 s a run under the sanitizers,
# where cone and linear with every check took 2 s and the recipe runs six.
selection=(--filter uniform_cone --check chi2 --check roundtrip --check consistency --samples 20000 --color never)
export VALIDATE=$validate SHARDS=4 OUT=$work/run

whole_status=0
"$validate" "${selection[@]}" --progress none > "$work/whole.txt" || whole_status=$?
[ "$whole_status" -le 1 ] || { cat "$work/whole.txt"; fail "the unsharded run exited $whole_status"; }

# Slurm: tasks 1, 2 and 4 of the array ran; task 3 was lost (a node died).
for task in 1 2 4; do
  SLURM_ARRAY_TASK_ID=$task SLURM_ARRAY_TASK_COUNT=4 sh "$script" "${selection[@]}" > "$work/task$task.log" 2>&1 ||
    { cat "$work/task$task.log"; fail "Slurm task $task failed"; }
done
ls "$work/run" > "$work/files.txt"
[ "$(wc -l < "$work/files.txt")" -eq 3 ] && grep -qx 'shard-4-of-4.json' "$work/files.txt" ||
  fail "the Slurm tasks did not write shard-I-of-4.json: $(cat "$work/files.txt")"

# The merge refuses the partial set, naming what is missing; --missing-shards lists it alone.
status=0
"$validate" --merge "$work"/run/shard-*-of-4.json > "$work/partial.txt" 2>&1 || status=$?
[ "$status" -eq 2 ] && grep -q 'shards missing: 3/4' "$work/partial.txt" || { cat "$work/partial.txt"; fail "a partial merge"; }
"$validate" --merge "$work"/run/shard-*-of-4.json --missing-shards > "$work/missing.txt" ||
  { cat "$work/missing.txt"; fail "--missing-shards failed"; }
[ "$(cat "$work/missing.txt")" = "3/4" ] || fail "--missing-shards says '$(cat "$work/missing.txt")', not 3/4"
# (What a resubmission takes: sbatch --array=$(cut -d/ -f1 missing.txt | paste -sd,) ...)
[ "$(cut -d/ -f1 "$work/missing.txt" | paste -sd,)" = "3" ] || fail "the array list of the missing shards"

# The lost shard again, as a Kubernetes indexed pod (index 2 is shard 3); shard 1
# again as a CI matrix entry (the same file, the same result).
JOB_COMPLETION_INDEX=2 sh "$script" "${selection[@]}" > "$work/pod.log" 2>&1 || { cat "$work/pod.log"; fail "the pod failed"; }
SHARD=1 sh "$script" "${selection[@]}" > "$work/matrix.log" 2>&1 || { cat "$work/matrix.log"; fail "the matrix job failed"; }
[ -z "$("$validate" --merge "$work"/run/shard-*-of-4.json --missing-shards)" ] || fail "shards still missing"

# What came back merges into the unsharded run: the same rows, the same exit status.
status_merged=0
"$validate" --merge "$work"/run/shard-*-of-4.json --color never --junit "$work/all.xml" > "$work/merged.txt" 2>&1 ||
  status_merged=$?
[ "$status_merged" -eq "$whole_status" ] || { cat "$work/merged.txt"; fail "merged exit $status_merged, unsharded $whole_status"; }
rows() { grep -E '^(pass|FAIL|ERROR|n/a) ' "$1"; }
[ -n "$(rows "$work/whole.txt")" ] && [ "$(rows "$work/merged.txt")" = "$(rows "$work/whole.txt")" ] ||
  { diff <(rows "$work/whole.txt") <(rows "$work/merged.txt"); fail "the merged rows are not the unsharded run's"; }

# Without SHARDS, or without an index, the script says what it needs.
! env -u SHARDS sh "$script" --all > "$work/no_shards.txt" 2>&1 && grep -q 'set SHARDS' "$work/no_shards.txt" ||
  fail "no message without SHARDS"
echo "shard recipe: 4 shards over Slurm, Kubernetes and a CI matrix; the missing one named, rerun, merged"
