#!/usr/bin/env bash
# One session of a batch (docs/batch.md). The INDEX-th line (1-based) of LIST is either
#   SCENARIO.yaml                 a scripted scenario, run with `prostatesim insert`, or
#   SCENARIO.yaml RECORDING       a trainee's recording, replayed with
#                                 `prostatesim replay SCENARIO --recording RECORDING --report DIR`.
# Results (metrics.json with its score, report.png, force-depth CSVs) go to
# OUTROOT/<trainee>/<session>, where <trainee> is the folder holding the recording (or scenario)
# and <session> its file name without the extension. INDEX defaults to $SLURM_ARRAY_TASK_ID, so
# GNU parallel and a Slurm job array run this script unchanged.
# Usage: session_job.sh LIST OUTROOT [INDEX]      (PROSTATESIM: the binary, default: prostatesim)
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: session_job.sh LIST OUTROOT [INDEX]" >&2; exit 2; }
list=$1
outroot=$2
index=${3:-${SLURM_ARRAY_TASK_ID:?give INDEX or run as a Slurm array task}}
bin=${PROSTATESIM:-prostatesim}
line=$(sed -n "${index}p" "$list")
[ -n "$line" ] || { echo "session_job.sh: $list:$index: no such line" >&2; exit 2; }
read -r scenario recording extra <<< "$line"
[ -z "${extra:-}" ] || { echo "session_job.sh: $list:$index: expected 'SCENARIO.yaml [RECORDING]', got: $line" >&2; exit 2; }
session_file=${recording:-$scenario}
name=$(basename "$session_file")
name=${name%.*}
trainee=$(basename "$(dirname "$session_file")")   # sessions are filed as <trainee>/<session>.<ext>
out="$outroot/$trainee/$name"
if [ -z "${recording:-}" ]; then
  exec "$bin" insert "$scenario" --trainee "$trainee" --session "$name" --out "$out"
else
  exec "$bin" replay "$scenario" --recording "$recording" --trainee "$trainee" --session "$name" --report "$out"
fi
