#!/usr/bin/env bash
# Install everything VibroImpact needs on a Debian machine (idempotent, quiet when all is there).
#   apt: C compiler, cmake, pkg-config, SUNDIALS 6.4 (libsundials-dev), Criterion (libcriterion-dev),
#        valgrind (the memory check of the FMU binary in tools/test.sh)
#   pip: fmpy, numpy, scipy, matplotlib, pytest, pytest-timeout, libcosimpy, dask, distributed, tqdm  (into $PYTHON, default python3)
set -euo pipefail

PYTHON=${PYTHON:-python3}
APT_PKGS=(gcc make cmake pkg-config libsundials-dev libcriterion-dev valgrind python3)
PIP_PKGS=(fmpy numpy scipy matplotlib pytest pytest-timeout libcosimpy dask distributed tqdm)
PY_MODULES="fmpy numpy scipy matplotlib pytest pytest_timeout libcosimpy dask distributed tqdm"

missing=()
for p in "${APT_PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO=sudo
  echo "setup: apt-get install ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ! "$PYTHON" -c "import importlib.util, sys; sys.exit(any(importlib.util.find_spec(m) is None for m in '$PY_MODULES'.split()))" 2>/dev/null; then
  echo "setup: pip install ${PIP_PKGS[*]}"
  "$PYTHON" -m pip install --quiet --disable-pip-version-check --root-user-action=ignore "${PIP_PKGS[@]}"
fi

# ---- the libFuzzer harness (tests/fuzz): clang with its sanitizer and libFuzzer runtimes ----------------
FUZZ_APT_PKGS=(clang libclang-rt-14-dev)
fuzz_missing=()
for p in "${FUZZ_APT_PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || fuzz_missing+=("$p")
done
if [ ${#fuzz_missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO=sudo
  echo "setup: apt-get install ${fuzz_missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${fuzz_missing[@]}" >/dev/null
fi
