#!/usr/bin/env bash
# Fails when a comment in engine/, app/, render/, haptics/ or config/ narrates the history of the
# work: a round of it ("round 27", "rounds 17-19") or a date ("2026-12-07", "Dec 2026", "7 Dec
# 2026", "05:40 UTC"). Comments say what is true now and why; how it got there belongs in the
# commit messages. Citations (an author and a year) and dates in code or data are not comments
# and pass. Comments are the text after // (and /* or a leading *) in C and C++ files, after # in
# YAML, CMake, shell and Python files.
#   bash scripts/check_history_comments.sh [ROOT]      # ROOT: the repository root by default
# Prints FILE:LINE:TEXT for each finding. Exit status: 0 none, 1 findings, 2 bad usage.
# CTest runs it as history_comments, and history_comments_fixture on tests/history/fixture.
set -uo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
if [[ ! -d $root ]]; then
  echo "check_history_comments: '$root' is not a folder" >&2
  exit 2
fi
cd "$root" || exit 2
dirs=()
for d in engine app render haptics config; do [[ -d $d ]] && dirs+=("$d"); done
if ((${#dirs[@]} == 0)); then
  echo "check_history_comments: none of engine/ app/ render/ haptics/ config/ under '$root'" >&2
  exit 2
fi

month='(jan(uary)?|feb(ruary)?|mar(ch)?|apr(il)?|may|june?|july?|aug(ust)?|sept?(ember)?|oct(ober)?|nov(ember)?|dec(ember)?)\b\.?'
year='(19|20)[0-9]{2}'
narration="\\brounds? [0-9]+|\\b${year}-[01][0-9]-[0-3][0-9]\\b|\\b${month} ([0-3]?[0-9],? )?${year}\\b"
narration+="|\\b[0-3]?[0-9] ${month},? ${year}\\b|\\b[0-2]?[0-9]:[0-5][0-9] ?utc\\b"

status=0
report() {  # grep's status: 0 found, 1 none, 2 error
  local rc=$1
  if ((rc == 0)); then status=1; elif ((rc > 1)); then exit 2; fi
}
grep -rnIiE --include='*.h' --include='*.hpp' --include='*.c' --include='*.cc' --include='*.cpp' --include='*.inl' \
  "(//|/\\*|^[[:space:]]*\\*).*(${narration})" "${dirs[@]}"
report $?
grep -rnIiE --include='*.yaml' --include='*.yml' --include='CMakeLists.txt' --include='*.cmake' --include='*.sh' \
  --include='*.py' "#.*(${narration})" "${dirs[@]}"
report $?
if ((status != 0)); then
  echo "check_history_comments: comments above narrate a round or a date; say what is true now and why," >&2
  echo "and put the history in the commit message" >&2
fi
exit $status
