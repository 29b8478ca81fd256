#!/usr/bin/env bash
# The vehicle-track example in one command: install what is missing, build the three FMUs
# (build/VibroImpact.fmu, build/Track.fmu, build/Vehicle.fmu), run the study against the monolithic
# reference with the fmpy master and with libcosim, and write the results and figures into
# examples/vehicle-track/results/ (not committed). Extra arguments go to study.py
# (e.g. --quick for a 30 ms run on three steps, --gallery to refresh doc/).
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
PY=$("$ROOT/tools/setup.sh" --example) # the main job's installs and libcosimpy
cmake -S "$ROOT" -B "$ROOT/build" -DVI_FMU_ONLY=OFF -DPython3_EXECUTABLE="$PY" >/dev/null
cmake --build "$ROOT/build" -j"$(nproc)" >/dev/null
cd "$HERE"
"$PY" study.py --build "$ROOT/build" --out "$HERE/results" "$@"
