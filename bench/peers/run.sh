#!/usr/bin/env bash
# One command for the Exudyn peer benchmark: set up bench/peers/.venv (Exudyn
# 1.13.6 and numpy from PyPI) and run the work-precision grid on the spin-up
# beam, writing bench/peers/results/exudyn.csv.
#   bench/peers/run.sh              full grid (about 10 min CPU)
#   bench/peers/run.sh --quick      small grid, one repetition (under a minute)
#   bench/peers/run.sh --reference  also regenerate bench/reference/*.csv first
#                                   (about 26 min CPU, two processes)
# Other arguments are passed to spin_up_peer.py. CI never needs this.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/setup.sh"
py="$here/.venv/bin/python"
args=()
for a in "$@"; do
    if [ "$a" = "--reference" ]; then
        "$py" "$here/spin_up_reference.py" --jobs 2
    else
        args+=("$a")
    fi
done
"$py" "$here/spin_up_peer.py" ${args[@]+"${args[@]}"}
