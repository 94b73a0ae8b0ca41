#!/usr/bin/env bash
# Golden-file runner: golden.sh EXPECTED CMD [ARGS...]
# Runs CMD, appends its exit status to its merged stdout+stderr, and compares with EXPECTED.
# NESSHI_UPDATE_GOLDEN=1 rewrites EXPECTED instead of comparing.
set -u
expected=$1; shift
actual=$(mktemp)
trap 'rm -f "$actual"' EXIT
"$@" >"$actual" 2>&1
status=$?
echo "[exit $status]" >>"$actual"
if [ "${NESSHI_UPDATE_GOLDEN:-0}" = 1 ]; then
  cp "$actual" "$expected"
  exit 0
fi
if ! diff -u "$expected" "$actual"; then
  echo "golden mismatch: $expected (rerun with NESSHI_UPDATE_GOLDEN=1 to accept)"
  exit 1
fi
