#!/usr/bin/env bash
# One session of a batch (docs/batch.md): the INDEX-th line (1-based) of LIST is a recording
# (replayed with `prostatesim replay`) or a scenario .yaml (run with `prostatesim insert`); its
# results, metrics.json included, go to OUTROOT/<name>. INDEX defaults to $SLURM_ARRAY_TASK_ID,
# so GNU parallel and a Slurm job array run this script unchanged.
# Usage: session_job.sh LIST OUTROOT [INDEX]      (PROSTATESIM: the binary, default: prostatesim)
set -euo pipefail
list=$1
outroot=$2
index=${3:-${SLURM_ARRAY_TASK_ID:?give INDEX or run as a Slurm array task}}
bin=${PROSTATESIM:-prostatesim}
input=$(sed -n "${index}p" "$list")
[ -n "$input" ] || { echo "session_job.sh: $list has no line $index" >&2; exit 2; }
name=$(basename "$input")
name=${name%.*}
trainee=$(basename "$(dirname "$input")")   # recordings are filed as <trainee>/<session>.<ext>
case "$input" in
  *.yaml) exec "$bin" insert "$input" --trainee "$trainee" --session "$name" --out "$outroot/$trainee/$name" ;;
  *) exec "$bin" replay "$input" --out "$outroot/$trainee/$name" ;;
esac
