#!/usr/bin/env bash
# Every shipped scenario gives the same file on 1 and on 2 threads, every
# dataset and attribute bit for bit (run_scenarios.sh, compare.py). The same
# two scripts hold one build's files against another's, before and after a
# change that must not change behaviour.
#   threads_test.sh GRANFLOW SCENARIOS_DIR
set -u
granflow="$1"
scenarios="$2"
source "$(dirname "$0")/../cli/common.sh"
here="$(dirname "$0")"
GRANFLOW_THREADS=1 "$here/run_scenarios.sh" "$granflow" "$scenarios" "$work/one" > /dev/null || exit 1
GRANFLOW_THREADS=2 "$here/run_scenarios.sh" "$granflow" "$scenarios" "$work/two" > /dev/null || exit 1
/usr/bin/python3 "$here/compare.py" "$work/one" "$work/two"
