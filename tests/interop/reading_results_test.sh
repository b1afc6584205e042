#!/usr/bin/env bash
# docs/reading-results.md works as written: its shell commands (granflow run
# and export), its Python snippets (/usr/bin/python3) and its ParaView
# snippets (pvpython under Xvfb) run in a scratch directory and succeed.
# Skips (exit 77) where MDAnalysis, ASE, gsd or ParaView's Python is missing.
set -u
granflow="$(realpath "$1")"
source_dir="$2"
source "$(dirname "$0")/../cli/common.sh"
if ! /usr/bin/python3 -c "import MDAnalysis, ase, gsd" 2> /dev/null; then
  echo "skipped: MDAnalysis, ASE or gsd is not installed (apt-get install python3-mdanalysis python3-ase python3-gsd)"
  exit 77
fi
if ! command -v pvpython > /dev/null || ! command -v xvfb-run > /dev/null; then
  echo "skipped: ParaView's Python or Xvfb is not installed (apt-get install python3-paraview xvfb)"
  exit 77
fi
cd "$work"
cp -r "$source_dir/scenarios" .
# Blocks between ```sh / ```python / ```pvpython and ```.
/usr/bin/python3 - "$source_dir/docs/reading-results.md" "$granflow" "$(dirname "$(realpath "$0")")/with_xvfb.sh" <<'PY'
import re, subprocess, sys, warnings
text, granflow, with_xvfb = open(sys.argv[1]).read(), sys.argv[2], sys.argv[3]
blocks = re.findall(r"```(sh|python|pvpython)\n(.*?)```", text, re.S)
assert len(blocks) >= 5, f"only {len(blocks)} code blocks"
for kind, code in blocks:
    if kind == "sh":
        for line in code.splitlines():
            command = line.split("#")[0].strip()
            if not command: continue
            command = command.replace("build/granflow", granflow)
            subprocess.run(command, shell=True, check=True)
            print("ok:", line.strip())
    elif kind == "pvpython":
        open("snippet.py", "w").write(code)
        subprocess.run([with_xvfb, "pvpython", "snippet.py"], check=True)
        print("ok: pvpython snippet starting", code.splitlines()[0])
    else:
        warnings.simplefilter("ignore")
        exec(compile(code, "snippet", "exec"), {})
        print("ok: python snippet starting", code.splitlines()[0])
PY
