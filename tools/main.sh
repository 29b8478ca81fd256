#!/usr/bin/env bash
# Main job: install what is needed, build the FMU, simulate the paper's scenarios (results/), and map the
# frequency response with up/down continuation sweeps on Dask (results/sweeps/).
# Python: the interpreter tools/setup.sh chose ($PYTHON, or the virtual environment .venv/ made from it).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=$(./tools/setup.sh)
cmake -S . -B build -DPython3_EXECUTABLE="$PY" >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
"$PY" tools/paper.py "$@"
"$PY" tools/rolling.py "$@"
"$PY" tools/sweep_diagrams.py
