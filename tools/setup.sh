#!/usr/bin/env bash
# Install everything VibroImpact needs on a Debian machine; idempotent, quiet when all is there.
#
#   PY=$(./tools/setup.sh)     the Python interpreter to run everything with is the one line on stdout
#                              (all messages go to stderr)
#
# The interpreter: $PYTHON (default python3). When it refuses pip installs (Debian's own python3 is
# externally managed, PEP 668, or an interpreter without pip), a virtual environment .venv/ in the
# repository is made from it (python3-venv from apt when missing) and used instead.
# Into that interpreter: the package `vibroimpact` from this checkout, editable, with its test extra
# (its dependencies are listed once, in pyproject.toml); the build backend first, because the
# editable install runs without build isolation (no download when nothing changed).
# apt: C compiler, cmake, pkg-config, SUNDIALS 6.4 (libsundials-dev), Criterion (libcriterion-dev),
#      valgrind (the memory check of the FMU binary in tools/test.sh).
set -euo pipefail
exec 3>&1 1>&2 # stdout carries the interpreter only; everything else goes to stderr
cd "$(dirname "$0")/.."
ROOT=$(pwd)
export PATH="$PATH:$HOME/.cargo/bin" # cargo installs its programs there

APT_PKGS=(gcc make cmake pkg-config libsundials-dev libcriterion-dev valgrind python3)
PIP_PKGS=(scikit-build-core) # the build backend of pyproject.toml, for the editable install
CARGO_PKGS=()                # "program=crate": cargo install crate when program is not on PATH

need_apt() { APT_PKGS+=("$@"); }
need_pip() { PIP_PKGS+=("$@"); }
need_cargo() { CARGO_PKGS+=("$@"); }

# ---- extra installs: add one line per need here, e.g. -----------------------------------------------
#   need_apt gcc-mingw-w64-x86-64
#   need_pip some-package
#   need_cargo some-program=some-crate
need_cargo fmi-sim=fmi-sim # the Rust FMI simulator: the second importer of the Model Exchange and FMI 3.0 tests
need_apt clang libclang-rt-14-dev # clang with libFuzzer and the sanitizers: the fuzz harness (tests/fuzz)
need_apt locales # the locales the locale tests run in (tests/test_text.c, fmu-test/test_locale.py)
# ------------------------------------------------------------------------------------------------------

# ---- apt ----------------------------------------------------------------------------------------------
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
APT_UPDATED=""
apt_install() {
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  echo "setup: apt-get install ${missing[*]}"
  if [ -z "$APT_UPDATED" ]; then
    $SUDO apt-get update -qq
    APT_UPDATED=1
  fi
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}
# cargo: the one on the PATH or in ~/.cargo/bin (rustup's place); without one, rustup's installer puts a
# minimal current toolchain there (Debian 12's cargo is too old for the crates above), curl from apt
NEED_RUSTUP=""
if [ ${#CARGO_PKGS[@]} -gt 0 ] && ! command -v cargo >/dev/null; then
  for entry in "${CARGO_PKGS[@]}"; do command -v "${entry%%=*}" >/dev/null || NEED_RUSTUP=1; done
  [ -z "$NEED_RUSTUP" ] || need_apt curl ca-certificates
fi
apt_install "${APT_PKGS[@]}"

# ---- locales ------------------------------------------------------------------------------------------
# de_DE.UTF-8 (decimal point ',') and ps_AF.UTF-8 (U+066B, two bytes), in which tests/test_text.c and
# fmu-test/test_locale.py run
for loc in de_DE ps_AF; do
  if ! locale -a 2>/dev/null | grep -qix "$loc\.utf-\?8"; then
    echo "setup: localedef -i $loc -f UTF-8 $loc.UTF-8"
    $SUDO localedef -i "$loc" -f UTF-8 "$loc.UTF-8"
  fi
done

# ---- the interpreter ----------------------------------------------------------------------------------
PYTHON=${PYTHON:-python3}
BASE=$("$PYTHON" -c 'import sys; print(sys.executable)') || { echo "setup: no interpreter '$PYTHON' (PYTHON)"; exit 1; }
# pip may install into it: a virtual environment, or an interpreter with pip that is not externally managed
can_pip() {
  "$1" - <<'EOF' 2>/dev/null
import importlib.util, os, sys, sysconfig
venv = sys.prefix != sys.base_prefix
managed = os.path.exists(os.path.join(sysconfig.get_path("stdlib"), "EXTERNALLY-MANAGED"))
sys.exit(0 if importlib.util.find_spec("pip") and (venv or not managed) else 1)
EOF
}
if can_pip "$BASE"; then
  PY=$BASE
else
  PY="$ROOT/.venv/bin/python"
  base_id=$("$BASE" -c 'import sys; print(sys.base_prefix, sys.version_info[:2])')
  if ! [ -x "$PY" ] || [ "$("$PY" -c 'import sys; print(sys.base_prefix, sys.version_info[:2])' 2>/dev/null)" != "$base_id" ] \
      || ! can_pip "$PY"; then
    if ! "$BASE" -c 'import ensurepip, venv' 2>/dev/null; then
      ver=$("$BASE" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
      pkg=python$ver-venv
      apt-cache show "$pkg" >/dev/null 2>&1 || pkg=python3-venv
      apt_install "$pkg"
    fi
    echo "setup: $BASE does not take pip installs; making the virtual environment .venv/ (run everything with $PY)"
    rm -rf "$ROOT/.venv"
    "$BASE" -m venv "$ROOT/.venv"
  fi
fi

# ---- pip ----------------------------------------------------------------------------------------------
PIP=("$PY" -m pip install --quiet --disable-pip-version-check)
[ "$(id -u)" -ne 0 ] || PIP+=(--root-user-action=ignore)
missing=()
for p in "${PIP_PKGS[@]}"; do
  "$PY" -c "import importlib.metadata as m, sys; m.distribution(sys.argv[1])" "${p%%[<>=!~;[]*}" 2>/dev/null \
    || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: pip install ${missing[*]}"
  "${PIP[@]}" "${missing[@]}"
fi
# the package, editable, unless it is installed from this checkout since pyproject.toml last changed and
# every requirement it declares (test extra included) is there
if ! "$PY" - "$ROOT" <<'EOF' 2>/dev/null; then
import importlib.metadata as m, json, os, pathlib, re, sys
root = pathlib.Path(sys.argv[1]).resolve()
d = m.distribution("vibroimpact")
url = [f for f in d.files if f.name == "direct_url.json"][0]
info = json.loads(url.read_text())
assert info.get("dir_info", {}).get("editable") and info["url"] == root.as_uri()
assert os.path.getmtime(d.locate_file(url)) >= os.path.getmtime(root / "pyproject.toml")
for r in d.requires or []:
    m.distribution(re.match(r"[A-Za-z0-9._-]+", r).group(0))
EOF
  echo "setup: pip install -e .[test] (the vibroimpact package of this checkout)"
  "${PIP[@]}" --no-build-isolation -e "$ROOT[test]"
fi

# ---- cargo --------------------------------------------------------------------------------------------
if [ -n "$NEED_RUSTUP" ]; then
  echo "setup: rustup (minimal toolchain) into ~/.cargo"
  curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --quiet --profile minimal --no-modify-path >/dev/null
fi
for entry in "${CARGO_PKGS[@]}"; do
  program=${entry%%=*} crate=${entry#*=}
  if ! command -v "$program" >/dev/null; then
    echo "setup: cargo install $crate"
    cargo install --quiet --locked "$crate"
  fi
done

echo "$PY" >&3
