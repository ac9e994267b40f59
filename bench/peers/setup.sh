#!/usr/bin/env bash
# Creates bench/peers/.venv (gitignored) with the peer engines used by the
# benchmark scripts in this directory: Exudyn 1.13.6 and numpy, from PyPI.
# Idempotent: an existing venv that already has the pinned versions is kept.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
venv="$here/.venv"
python="${PYTHON:-python3}"
exudyn_version="1.13.6"

if [ ! -x "$venv/bin/python" ]; then
    echo "setup: creating $venv with $("$python" --version 2>&1)" >&2
    "$python" -m venv "$venv"
fi

if "$venv/bin/python" - "$exudyn_version" <<'PY' 2>/dev/null
import sys, importlib.metadata as md
assert md.version("exudyn") == sys.argv[1]
md.version("numpy")
PY
then
    echo "setup: exudyn $exudyn_version and numpy already installed in $venv" >&2
else
    echo "setup: installing exudyn==$exudyn_version and numpy" >&2
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet "exudyn==$exudyn_version" numpy
fi

"$venv/bin/python" -c 'import exudyn, numpy; print("setup: exudyn", exudyn.__version__, "numpy", numpy.__version__)'
