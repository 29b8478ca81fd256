#!/usr/bin/env bash
# Main job: install what is needed, build the FMU, simulate the paper's scenarios (results/), and map the
# frequency response with up/down continuation sweeps on Dask (results/sweeps/).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
./tools/setup.sh
cmake -S . -B build -DPython3_EXECUTABLE="$(command -v "$PYTHON")" >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
"$PYTHON" tools/paper.py "$@"
"$PYTHON" tools/rolling.py "$@"
"$PYTHON" tools/sweep_diagrams.py
