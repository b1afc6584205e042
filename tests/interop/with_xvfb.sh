#!/usr/bin/env bash
# Runs a command under a virtual X server (Xvfb), as ParaView's renderer
# needs one. The display is picked from a random start, so that tests run
# side by side do not race for the same one, and a start that loses its X
# connection anyway (seen under full ctest load, three times in a row once
# while the machine also compiled) is tried again after a pause that grows,
# up to five times; any other failure is the command's own.
#   with_xvfb.sh COMMAND [ARG ...]
set -u
log=$(mktemp)
trap 'rm -f "$log"' EXIT
for attempt in 1 2 3 4 5; do
  xvfb-run -a -n $((100 + RANDOM % 800)) -s "-screen 0 1024x768x24" "$@" 2>&1 | tee "$log"
  status=${PIPESTATUS[0]}
  grep -q "bad X server connection" "$log" || exit "$status"
  echo "X server connection lost (attempt $attempt); starting another" >&2
  sleep "$attempt"
done
exit "$status"
