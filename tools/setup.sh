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

# ---- fmi-sim: the Rust FMI simulator, the second importer of the Model Exchange tests ----------------
# `cargo install fmi-sim` with the cargo on the PATH or in ~/.cargo/bin (rustup's place); without one,
# rustup's installer puts a minimal current toolchain there (Debian 12's cargo is too old for fmi-sim).
export PATH="$PATH:$HOME/.cargo/bin"
if ! command -v fmi-sim >/dev/null; then
  if ! command -v cargo >/dev/null; then
    if ! command -v curl >/dev/null; then
      SUDO=""
      [ "$(id -u)" -eq 0 ] || SUDO=sudo
      DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends curl ca-certificates >/dev/null
    fi
    echo "setup: rustup (minimal toolchain) into ~/.cargo"
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --quiet --profile minimal --no-modify-path >/dev/null
  fi
  echo "setup: cargo install fmi-sim"
  cargo install --quiet --locked fmi-sim
fi
