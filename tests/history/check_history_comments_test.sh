#!/usr/bin/env bash
# CTest history_comments_fixture: runs scripts/check_history_comments.sh on tests/history/fixture
# and passes only when it exits 1 and reports exactly the fixture lines that carry the marker
# <narrates>: a check that misses a narration, or flags a citation, a date in code or data, or a
# folder it does not check, fails.
#   bash tests/history/check_history_comments_test.sh [CHECKER]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
checker=${1:-$here/../../scripts/check_history_comments.sh}
fixture=$here/fixture
out=$(bash "$checker" "$fixture" 2>/dev/null)
rc=$?
if ((rc != 1)); then
  echo "history_comments_fixture: the check exited $rc on the fixture, expected 1"
  exit 1
fi
reported=$(printf '%s\n' "$out" | cut -d: -f1,2 | sort)
expected=$(cd "$fixture" && grep -rn '<narrates>' . | sed 's|^\./||' | cut -d: -f1,2 | sort)
if [[ $reported != "$expected" ]]; then
  echo "history_comments_fixture: reported lines differ from the marked ones (< reported, > marked):"
  diff <(printf '%s\n' "$reported") <(printf '%s\n' "$expected")
  exit 1
fi
echo "history_comments_fixture: $(printf '%s\n' "$expected" | wc -l) marked narrations reported, nothing else"
