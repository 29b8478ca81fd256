#!/usr/bin/env bash
# Every test: install what is needed, build (warnings are errors), C unit tests and the valgrind memcheck
# of the FMU binary (ctest), FMU tests (pytest), then the C tests and the FMU driver again built with
# AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/). Any failure or memory report fails the run.
# Python: the interpreter tools/setup.sh chose ($PYTHON, or the virtual environment .venv/ made from it).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=$(./tools/setup.sh)
export PATH="$PATH:$HOME/.cargo/bin"
cmake -S . -B build -DVI_WERROR=ON -DVI_REQUIRE_TESTS=ON -DPython3_EXECUTABLE="$PY" >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
(cd build && ctest --output-on-failure)
"$PY" -m pytest -q fmu-test
# the whole FMU suite again with the other solvers (bdf, adams, dop853; the default is auto); libcosim uses
# the FMU's default
for solver in 1 2 3; do VI_SOLVER=$solver "$PY" -m pytest -q fmu-test -k "not libcosimpy"; done
cmake -S . -B build-asan -DVI_SANITIZE=ON -DVI_WERROR=ON -DVI_REQUIRE_TESTS=ON -DPython3_EXECUTABLE="$PY" >/dev/null
cmake --build build-asan -j"$(nproc)" >/dev/null
(cd build-asan && ctest --output-on-failure)

# Cross-platform: the release FMUs (tools/release.sh: dist/fmi2 with linux64 and win64, the aarch64
# libraries), the win64 DLLs under wine64 and the aarch64 libraries under qemu-user against linux64.
PYTHON="$PY" ./tools/cross_test.sh
