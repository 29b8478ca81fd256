#!/usr/bin/env bash
# Every test: install what is needed, build (warnings are errors), C unit tests (ctest), FMU tests (pytest).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
./tools/setup.sh
cmake -S . -B build -DVI_WERROR=ON -DVI_REQUIRE_TESTS=ON -DPython3_EXECUTABLE="$(command -v "$PYTHON")" >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
(cd build && ctest --output-on-failure)
"$PYTHON" -m pytest -q fmu-test
# the whole FMU suite again with the other two solvers (adams, dop853); libcosim uses the FMU's default
for solver in 2 3; do VI_SOLVER=$solver "$PYTHON" -m pytest -q fmu-test -k "not libcosimpy"; done
