#!/bin/sh
# CLI check: run a command, require its exit status to be zero (ok) or non-zero (fail), and its
# combined output to match a grep pattern.  Usage: cli_check.sh ok|fail PATTERN command args...
want=$1; pattern=$2; shift 2
out=$("$@" 2>&1); rc=$?
if [ "$want" = ok ] && [ $rc -ne 0 ]; then echo "exit $rc, expected 0"; echo "$out"; exit 1; fi
if [ "$want" = fail ] && [ $rc -eq 0 ]; then echo "exit 0, expected failure"; echo "$out"; exit 1; fi
if [ $rc -gt 125 ]; then echo "crashed (exit $rc)"; echo "$out"; exit 1; fi
echo "$out" | grep -q -- "$pattern" || { echo "output does not match '$pattern':"; echo "$out"; exit 1; }
