#!/usr/bin/env bash
# Every test: install what is needed (tools/setup.sh --test: the main job's installs, then what the tests
# add, each install said so), build (warnings are errors), C unit tests and the valgrind memcheck of the
# FMU binary (ctest), the FMU built again against SUNDIALS 7.9 (tools/sundials7.sh, build/sundials7/),
# FMU tests (pytest; those the solver choice reaches again with each other solver), then the C tests, the FMU
# driver and part of the FMU tests again built with AddressSanitizer + UndefinedBehaviorSanitizer
# (build-asan/), those FMU tests there in de_DE.UTF-8. Any failure or memory report fails the run.
# Python: the interpreter tools/setup.sh chose ($PYTHON, or the virtual environment .venv/ made from it).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=$(./tools/setup.sh --test)
export PATH="$PATH:$HOME/.cargo/bin"
# everything, also where tools/main.sh configured the FMUs alone (VI_FMU_ONLY)
cmake -S . -B build -DVI_FMU_ONLY=OFF -DVI_WERROR=ON -DVI_REQUIRE_TESTS=ON -DPython3_EXECUTABLE="$PY" >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
(cd build && ctest --output-on-failure)
# SUNDIALS 7.9 (the sundials4py wheel, cached outside the clone): the FMUs, the solver tests and the memory
# check of both FMU binaries; fmu-test/test_sundials.py compares them with build/'s
PYTHON="$PY" ./tools/sundials7.sh
# the FMU tests, writing which of them VI_SOLVER reaches (fmu-test/conftest.py: a run without a solver of its
# own, a module that reads the solver under test)
SOLVER_TESTS=build/solver-tests.json
"$PY" -m pytest -q fmu-test --solver-tests-out "$SOLVER_TESTS"
# those again with the other solvers (bdf, adams, dop853; the default is auto); the tests marked libcosim
# (pytest.ini) run the FMU's default, whatever VI_SOLVER says
for solver in 1 2 3; do
  VI_SOLVER=$solver "$PY" -m pytest -q fmu-test -m "not libcosim" --solver-tests-from "$SOLVER_TESTS"
done
cmake -S . -B build-asan -DVI_SANITIZE=ON -DVI_WERROR=ON -DVI_REQUIRE_TESTS=ON -DPython3_EXECUTABLE="$PY" >/dev/null
cmake --build build-asan -j"$(nproc)" >/dev/null
(cd build-asan && ctest --output-on-failure)
# The FMU tests of robustness, FMU states, Model Exchange, FMI 3.0, profile files and messages again (the
# files of SANITIZED_TESTS, not the whole suite), against the sanitized FMUs of build-asan/ (VI_FMU) with
# the compiler's sanitizer runtimes preloaded into Python, and in de_DE.UTF-8 (decimal point ','; --locale
# sets LC_ALL before any FMU is loaded): the numbers the FMU reads (profile files) and writes (messages,
# logged values) must be what the tests expect in the C locale. Leaks are not reported here (the
# interpreter's own; the drivers above check the FMU's); any other report ends the run. --capture=sys: the
# report goes to stderr, not into pytest's capture of a process that dies.
CC_ASAN=$(sed -n 's/^CMAKE_C_COMPILER:[A-Z]*=//p' build-asan/CMakeCache.txt)
SAN_RUNTIMES=()
for lib in libasan.so libubsan.so; do
  path=$("$CC_ASAN" -print-file-name="$lib")
  [ -f "$path" ] || { echo "test.sh: $CC_ASAN has no $lib (Debian: gcc installs libasan8 and libubsan1)" >&2; exit 1; }
  SAN_RUNTIMES+=("$path")
done
SANITIZED_TESTS=(fmu-test/test_bounds.py fmu-test/test_extremes.py fmu-test/test_fuzz_findings.py fmu-test/test_status.py
                 fmu-test/test_fmi.py fmu-test/test_read_all.py fmu-test/test_rollback.py fmu-test/test_state.py
                 fmu-test/test_me_*.py fmu-test/test_fmi3*.py fmu-test/test_bad_inputs.py fmu-test/test_rolling.py
                 fmu-test/test_validity.py fmu-test/test_messages.py)
LD_PRELOAD="$(IFS=:; echo "${SAN_RUNTIMES[*]}")" ASAN_OPTIONS=detect_leaks=0:halt_on_error=1 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 VI_FMU="$PWD/build-asan/VibroImpact.fmu" \
  "$PY" -m pytest -q --capture=sys --locale de_DE.UTF-8 "${SANITIZED_TESTS[@]}"

# Cross-platform: the release FMUs (tools/release.sh: dist/fmi2 with linux64 and win64, the aarch64
# libraries), the win64 DLLs under wine64 and the aarch64 libraries under qemu-user against linux64.
PYTHON="$PY" ./tools/cross_test.sh
