#!/usr/bin/env bash
# docs/reading-results.md works as written: its shell commands (granflow run
# and export) and its Python snippets run in a scratch directory and succeed.
# Skips (exit 77) where MDAnalysis is not installed.
set -u
granflow="$(realpath "$1")"
source_dir="$2"
source "$(dirname "$0")/../cli/common.sh"
if ! /usr/bin/python3 -c "import MDAnalysis" 2> /dev/null; then
  echo "skipped: MDAnalysis is not installed (apt-get install python3-mdanalysis)"
  exit 77
fi
cd "$work"
cp -r "$source_dir/scenarios" .
# Blocks between ```sh / ```python and ```; `paraview` is a program this test does not have.
/usr/bin/python3 - "$source_dir/docs/reading-results.md" "$granflow" <<'PY'
import re, subprocess, sys, warnings
text, granflow = open(sys.argv[1]).read(), sys.argv[2]
blocks = re.findall(r"```(sh|python)\n(.*?)```", text, re.S)
assert len(blocks) >= 5, f"only {len(blocks)} code blocks"
for kind, code in blocks:
    if kind == "sh":
        for line in code.splitlines():
            command = line.split("#")[0].strip()
            if not command or command.startswith("paraview"): continue
            command = command.replace("build/granflow", granflow)
            subprocess.run(command, shell=True, check=True)
            print("ok:", line.strip())
    else:
        warnings.simplefilter("ignore")
        exec(compile(code, "snippet", "exec"), {})
        print("ok: python snippet starting", code.splitlines()[0])
PY
