#!/bin/sh
# One shard of a warpcheck run on a cluster or CI engine you already have:
# the shard's index comes from the engine's own variable, the shard count from
# SHARDS (fixed for the run, so that a rerun of some shards is the same run).
#   Slurm job array (sbatch --array=1-N): SLURM_ARRAY_TASK_ID, 1 to N
#   Kubernetes Indexed Job (completionMode: Indexed): JOB_COMPLETION_INDEX, 0 to N-1
#   a CI matrix (GitHub Actions, GitLab parallel:matrix, ...): SHARD, 1 to N
# Usage: SHARDS=N [VALIDATE=program] [OUT=folder] warpcheck_shard.sh SELECTION...
# e.g. SHARDS=16 OUT=/shared/run42 warpcheck_shard.sh --all --samples 1e7
# writes OUT/shard-I-of-N.json; validate --merge OUT/shard-*-of-N.json merges them.
set -eu
n=${SHARDS:?set SHARDS to the shard count of the run}
if [ -n "${SLURM_ARRAY_TASK_ID:-}" ]; then
  i=$SLURM_ARRAY_TASK_ID
elif [ -n "${JOB_COMPLETION_INDEX:-}" ]; then
  i=$((JOB_COMPLETION_INDEX + 1))
else
  i=${SHARD:?set SHARD (1 to SHARDS), or run as a Slurm array task or a Kubernetes indexed pod}
fi
out=${OUT:-.}
mkdir -p "$out"
# Exit 1 (a check failed) is a result, not a failure of the job: the merge tells.
status=0
"${VALIDATE:-validate}" "$@" --shard "$i/$n" --json "$out/shard-$i-of-$n.json" --progress log || status=$?
[ "$status" -le 1 ] || exit "$status"
