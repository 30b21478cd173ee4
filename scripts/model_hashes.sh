#!/usr/bin/env bash
# Prints "FILE HASH" for every scenario under config/ and config/validation/: the compiled model's
# fingerprint from `prostatesim check` (engine/scenario/model_hash.h). Used to show that a change
# meant to be behaviour-free (a refactoring of engine/scenario/compile*.cpp, a CMake split) leaves
# every compiled model bit-identical:
#   bash scripts/model_hashes.sh build/app/prostatesim > before.txt   # on the old commit
#   bash scripts/model_hashes.sh build/app/prostatesim > after.txt    # on the new one
#   diff before.txt after.txt                                     # no output: identical
# Exit status: 0, or 1 when a scenario fails to compile (its line then reads "FILE error").
set -uo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/app/prostatesim}
status=0
for f in config/*.yaml config/validation/*.yaml; do
  h=$("$bin" check "$f" 2>/dev/null | sed -n 's/^model hash \([0-9a-f]\{16\}\)$/\1/p')
  if [[ -z "$h" ]]; then h=error; status=1; fi
  echo "$f $h"
done
exit $status
