#!/usr/bin/env bash
# Runs an `sss simulate` or `sss table` job on a Slurm cluster as a job array of N shards plus a
# merge job that starts when every shard has succeeded (--dependency=afterok). Each array task
# traces its slice with `--shard auto` (SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN of
# SLURM_ARRAY_TASK_COUNT); `sss merge` then writes exactly what one machine would have written.
#
#   scripts/slurm/submit.sh --shards N --out DIR [--wait] -- table --g 0,0.5,0.9 --eta 1.3,1.4 --photons 1e6
#   scripts/slurm/submit.sh --shards 32 --out runs/skin1 -- simulate skin1 --photons 1e9
#
# Shards go to DIR/shards, logs to DIR/logs, the merged outputs to DIR. Prints the two job ids.
# The options a user edits are below (or set them in the environment):
PARTITION=${PARTITION:-}            # sbatch --partition (empty: the cluster's default)
TIME=${TIME:-04:00:00}              # sbatch --time per shard
CPUS_PER_TASK=${CPUS_PER_TASK:-4}   # sbatch --cpus-per-task; sss uses that many threads
MERGE_TIME=${MERGE_TIME:-00:30:00}  # sbatch --time of the merge job
SSS=${SSS:-sss}                     # the sss binary, as the compute nodes find it
EXTRA_SBATCH=${EXTRA_SBATCH:-}      # anything else for sbatch, e.g. "--account=lab --mem=4G"
set -euo pipefail

usage() { echo "usage: $0 --shards N --out DIR [--wait] -- simulate|table ARGS…" >&2; exit 2; }
shards=""; out=""; wait=""
while [[ $# -gt 0 ]]; do
    case "$1" in
        --shards) shards=${2:-}; shift 2 ;;
        --out) out=${2:-}; shift 2 ;;
        --wait) wait=1; shift ;;
        --) shift; break ;;
        *) usage ;;
    esac
done
[[ "$shards" =~ ^[1-9][0-9]*$ && -n "$out" && $# -ge 1 ]] || usage
case "$1" in simulate|table) ;; *) echo "the job must be sss simulate or sss table, not $1" >&2; exit 2 ;; esac
for a in "$@"; do
    case "$a" in --out|--out=*|--shard|--shard=*|--threads|--threads=*)
        echo "$a is set by this script (--out DIR/shards, --shard auto, --threads from --cpus-per-task)" >&2; exit 2 ;;
    esac
done
command -v sbatch >/dev/null || { echo "sbatch not found: run this on a Slurm login node" >&2; exit 3; }

mkdir -p "$out/shards" "$out/logs"
out=$(cd "$out" && pwd)
common=(--parsable --chdir "$out" ${PARTITION:+--partition "$PARTITION"})
read -r -a extra <<< "$EXTRA_SBATCH"

job=$(printf '%q ' "$SSS" "$@" --shard auto --out "$out/shards")
array=$(sbatch "${common[@]}" "${extra[@]}" --job-name "sss-$1" --array "0-$((shards - 1))" \
    --cpus-per-task "$CPUS_PER_TASK" --time "$TIME" --output "$out/logs/%x-%A_%a.out" \
    --wrap "$job --threads \${SLURM_CPUS_PER_TASK:-1}")
array=${array%%;*}

merge=$(printf '%q ' "$SSS" merge --out "$out")
merge_id=$(sbatch "${common[@]}" "${extra[@]}" --job-name "sss-merge" --dependency "afterok:$array" \
    --kill-on-invalid-dep=yes --cpus-per-task 1 --time "$MERGE_TIME" --output "$out/logs/%x-%j.out" \
    ${wait:+--wait} --wrap "$merge $(printf '%q' "$out/shards")/*-of-$shards.json")
merge_id=${merge_id%%;*}
echo "array job $array ($shards shards of sss $1), merge job $merge_id → $out"
