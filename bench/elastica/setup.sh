#!/usr/bin/env bash
# Creates bench/elastica/.venv (gitignored) with the pinned numpy and scipy from
# PyPI that bench/elastica/elastica.py uses.
# Idempotent: an existing venv that already has the pinned versions is kept.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
venv="$here/.venv"
python="${PYTHON:-python3}"
numpy_version="2.2.6"
scipy_version="1.15.3"

if [ ! -x "$venv/bin/python" ]; then
    echo "setup: creating $venv with $("$python" --version 2>&1)" >&2
    "$python" -m venv "$venv"
fi

if "$venv/bin/python" - "$numpy_version" "$scipy_version" <<'PY' 2>/dev/null
import sys, importlib.metadata as md
assert md.version("numpy") == sys.argv[1]
assert md.version("scipy") == sys.argv[2]
PY
then
    echo "setup: numpy $numpy_version and scipy $scipy_version already installed in $venv" >&2
else
    echo "setup: installing numpy==$numpy_version scipy==$scipy_version" >&2
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet "numpy==$numpy_version" "scipy==$scipy_version"
fi

"$venv/bin/python" -c 'import numpy, scipy; print("setup: numpy", numpy.__version__, "scipy", scipy.__version__)'
