#!/usr/bin/env bash
# Runs one interop test with the program that has its tool: pvpython under
# Xvfb (with_xvfb.sh) for ParaView, Debian's /usr/bin/python3 for MDAnalysis, ASE and gsd.
# Exits 77 (skipped, saying why) where the program is missing.
#   tool_test.sh paraview|mdanalysis|ase|gsd OUTPUT_DIR
set -u
tool="$1"
directory="$2"
here="$(cd "$(dirname "$0")" && pwd)"
if [[ "$tool" == paraview ]]; then
  for program in pvpython xvfb-run; do
    command -v "$program" > /dev/null || { echo "skipped: $program is not installed (apt-get install paraview xvfb)"; exit 77; }
  done
  exec "$here/with_xvfb.sh" pvpython "$here/paraview_test.py" "$directory"
fi
exec /usr/bin/python3 -W ignore "$here/${tool}_test.py" "$directory"
