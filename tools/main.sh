#!/usr/bin/env bash
# Main job: install what is needed, build the FMU, simulate the paper's scenarios (results/), roll the
# wheel over a corrugated rail (results/rolling/), and map the frequency response with up/down
# continuation sweeps on Dask (results/diagrams/). Arguments go to `vibroimpact paper` (scenario names,
# --gallery DIR); --gallery DIR also gives the rolling and diagrams figures' copies to DIR (the
# documentation's: ./tools/main.sh --gallery doc/gallery).
# Installs what the main job uses and nothing else (tools/setup.sh: compiler, CMake, SUNDIALS, the Python
# side) and builds the FMUs alone (VI_FMU_ONLY: no test program, no fuzz harness; tools/test.sh builds those).
# Python: the interpreter tools/setup.sh chose ($PYTHON, or the virtual environment .venv/ made from it).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=$(./tools/setup.sh)
cmake -S . -B build -DVI_FMU_ONLY=ON -DPython3_EXECUTABLE="$PY" >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
"$PY" -m vibroimpact paper "$@"
gallery=()
args=("$@")
for i in "${!args[@]}"; do
  [ "${args[$i]}" != --gallery ] || gallery=(--gallery "${args[$((i + 1))]:-}")
done
"$PY" -m vibroimpact rolling "${gallery[@]}"
"$PY" -m vibroimpact diagrams "${gallery[@]}"
