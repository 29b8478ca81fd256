#!/usr/bin/env bash
# The FMU built against SUNDIALS 7.9 (part of tools/test.sh): the second SUNDIALS the build supports
# (cmake/vi_sundials.cmake), next to Debian's 6.4.1 of build/.
#
# SUNDIALS 7.9.0 comes from the package index: the wheel sundials4py 7.9.0 (CPython 3.12, manylinux_2_28
# x86_64) holds SUNDIALS' headers, static libraries and CMake package (CVODES, not CVODE). It is
# downloaded once (pip download, checked against the SHA-256 below) and unpacked into
# ${XDG_CACHE_HOME:-~/.cache}/vibroimpact/, beside the other inputs tools/release.sh keeps there.
# Then, in build/sundials7/ (Release, warnings are errors):
#   cmake -S . -B build/sundials7 -DSUNDIALS_DIR=<the wheel>/lib64/cmake/sundials
# and the FMUs (build/sundials7/VibroImpact.fmu, fmi3/VibroImpact.fmu), the solver's unit tests and the
# FMU drivers, whose ctest runs (the solver tests, valgrind's memory check of both FMU binaries) follow.
# fmu-test/test_sundials.py compares these FMUs with build/'s.
#
# Usage: tools/sundials7.sh   (PYTHON: the interpreter, as for tools/setup.sh; JOBS: default nproc)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
JOBS=${JOBS:-$(nproc)}
CACHE=${XDG_CACHE_HOME:-$HOME/.cache}/vibroimpact
VERSION=7.9.0
WHEEL=sundials4py-$VERSION-cp312-abi3-manylinux_2_27_x86_64.manylinux_2_28_x86_64.whl
SHA256=695cb4f356b451c65175ce67dff41240e79bc50d93a996896f5010c51bfa3a0d
PREFIX=$CACHE/sundials-$VERSION-wheel
BUILD=$ROOT/build/sundials7
PYTHON=${PYTHON:-$(./tools/setup.sh)}

die() { echo "sundials7: $*" >&2; exit 1; }

if [ "$(cat "$PREFIX/wheel-sha256" 2>/dev/null)" != "$SHA256" ]; then
  mkdir -p "$CACHE/wheels"
  if [ "$(sha256sum "$CACHE/wheels/$WHEEL" 2>/dev/null | cut -d' ' -f1)" != "$SHA256" ]; then
    echo "sundials7: pip download sundials4py==$VERSION (into $CACHE/wheels)" >&2
    rm -f "$CACHE/wheels/$WHEEL"
    "$PYTHON" -m pip download --quiet --disable-pip-version-check --no-deps --only-binary :all: \
      --python-version 3.12 --platform manylinux_2_28_x86_64 "sundials4py==$VERSION" -d "$CACHE/wheels" >&2 \
      || die "pip download sundials4py==$VERSION failed (the package index must be reachable once)"
    [ "$(sha256sum "$CACHE/wheels/$WHEEL" | cut -d' ' -f1)" = "$SHA256" ] \
      || die "$CACHE/wheels/$WHEEL: not the wheel this script knows (SHA-256 differs)"
  fi
  rm -rf "$PREFIX" "$PREFIX.partial"
  "$PYTHON" -m zipfile -e "$CACHE/wheels/$WHEEL" "$PREFIX.partial"
  [ -f "$PREFIX.partial/lib64/cmake/sundials/SUNDIALSConfig.cmake" ] || die "$WHEEL holds no lib64/cmake/sundials"
  echo "$SHA256" >"$PREFIX.partial/wheel-sha256"
  mv "$PREFIX.partial" "$PREFIX"
fi

log=$ROOT/build/sundials7.log
mkdir -p "$ROOT/build"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DVI_WERROR=ON -DVI_FUZZ=OFF -DPython3_EXECUTABLE="$PYTHON" \
  -DSUNDIALS_DIR="$PREFIX/lib64/cmake/sundials" >"$log" 2>&1 || { tail -n 30 "$log" >&2; die "configure failed ($log)"; }
grep -q "SUNDIALS $VERSION CVODES (static)" "$log" || die "the build did not take SUNDIALS $VERSION CVODES ($log)"
cmake --build "$BUILD" -j"$JOBS" --target VibroImpact_fmu VibroImpact_fmi3_fmu LayerTest test_solver fmu_driver \
  fmu3_driver >>"$log" 2>&1 || { tail -n 40 "$log" >&2; die "build failed ($log)"; }
(cd "$BUILD" && ctest --output-on-failure --no-tests=error -R '^(solver|fmu_driver_valgrind|fmu3_driver_valgrind)$') \
  || die "the ctest runs against SUNDIALS $VERSION failed"
echo "sundials7: build/sundials7/VibroImpact.fmu (SUNDIALS $VERSION CVODES) built and tested" >&2
