#!/bin/sh
# A Catch test name with ';' is split by catch_discover_tests (CMake lists), so CTest would run a
# filter that matches nothing and pass without running the case. Usage: check_test_names.sh TESTS_DIR
if grep -rn 'TEST_CASE("[^"]*;' "$1" --include=*.cpp; then
  echo "test names above contain ';' (CTest would never run them): use ',' instead"
  exit 1
fi
