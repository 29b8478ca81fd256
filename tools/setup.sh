#!/usr/bin/env bash
# Install what VibroImpact needs on a Debian machine, for one purpose; idempotent, quiet when all is there.
#
#   PY=$(./tools/setup.sh)            the main job (tools/main.sh): compiler, CMake, SUNDIALS, the Python side
#   PY=$(./tools/setup.sh --example)  also libcosimpy, the second master of examples/vehicle-track/run.sh
#   PY=$(./tools/setup.sh --release)  also what tools/release.sh needs: the cross compilers, wine64, qemu-user,
#                                     dpkg-dev, llvm, zig (pip package ziglang)
#   PY=$(./tools/setup.sh --test)     also what the tests need (tools/test.sh, tools/cross_test.sh): the release's,
#                                     Criterion, valgrind, clang with libFuzzer and the sanitizers, the locales,
#                                     pytest and libcosimpy, fmi-sim (Rust)
#   ./tools/setup.sh [--example|--release|--test] --list     print what that purpose installs, install nothing
#   ./tools/setup.sh [--example|--release|--test] --dry-run  check as usual, say what would be installed
#
# The interpreter to run everything with is the one line on stdout (all messages go to stderr):
# $PYTHON (default python3). When it refuses pip installs (Debian's own python3 is externally managed,
# PEP 668, or an interpreter without pip), a virtual environment .venv/ in the repository is made from
# it (python3-venv from apt when missing) and used instead.
# Into that interpreter: the package `vibroimpact` from this checkout, editable (its dependencies are
# listed once, in pyproject.toml; the tests add its test extra); the build backend first, because the
# editable install runs without build isolation (no download when nothing changed).
# fmi-sim (the tests' second FMI importer) is built by cargo into ~/.cargo/bin. Debian's cargo is used
# when its rustc is recent enough for fmi-sim (edition 2024: Rust 1.85); Debian 12's (1.63) is not, and
# then rustup's installer puts a minimal current toolchain into ~/.cargo, and says so.
# When something cannot be installed, the setup stops with a message naming it.
set -euo pipefail
exec 3>&1 1>&2 # stdout carries the interpreter only; everything else goes to stderr
cd "$(dirname "$0")/.."
ROOT=$(pwd)
export PATH="$PATH:$HOME/.cargo/bin" # cargo installs its programs there

PURPOSE=main LIST="" DRY=""
for arg in "$@"; do
  case $arg in
    --example) [ "$PURPOSE" = test ] || PURPOSE=example ;;
    --release) [ "$PURPOSE" = test ] || PURPOSE=release ;;
    --test) PURPOSE=test ;;
    --list) LIST=1 ;;
    --dry-run) DRY=1 ;;
    *) echo "setup: unknown option $arg (use --example, --release, --test, --list, --dry-run)"; exit 2 ;;
  esac
done

# ---- what each purpose installs ------------------------------------------------------------------------
# the main job: build the FMU (C compiler, make, CMake, SUNDIALS 6.4) and run the package
APT_PKGS=(gcc make cmake libsundials-dev python3)
PIP_PKGS=(scikit-build-core) # the build backend of pyproject.toml, for the editable install
EXTRAS=""                    # the package's extras (pyproject.toml) to install with it
CARGO_PKGS=()                # "program=crate@version": cargo install when program is not on the PATH
LOCALES=()                   # the locales to generate (localedef), e.g. de_DE
# program -> the package that installs it: checked after the installs (a missing one stops the setup)
declare -A PROGRAMS=([gcc]=gcc [cmake]=cmake [make]=make)
N_APT_MAIN=${#APT_PKGS[@]} N_PIP_MAIN=${#PIP_PKGS[@]} # the main job's; what follows is the purpose's

need_apt() { APT_PKGS+=("$@"); }
need_pip() { PIP_PKGS+=("$@"); }
need_cargo() { CARGO_PKGS+=("$@"); }
need_program() { PROGRAMS[$1]=$2; } # <program> <the package that installs it>

if [ "$PURPOSE" = example ]; then
  need_pip libcosimpy # the vehicle-track example's second master (libcosim); the tests' extra has it
fi
if [ "$PURPOSE" = release ] || [ "$PURPOSE" = test ]; then
  # tools/release.sh: the win64 and aarch64 cross builds, wine64 and qemu-user to run them
  # (tools/cross_test.sh), SUNDIALS' source package (apt-get source: dpkg-dev, xz-utils), llvm-objdump
  # and llvm-nm for the macOS binaries, zig cc their cross compiler
  need_apt gcc-mingw-w64-x86-64 binutils-mingw-w64-x86-64 wine64 gcc-aarch64-linux-gnu binutils-aarch64-linux-gnu \
           libc6-dev-arm64-cross qemu-user dpkg-dev xz-utils llvm
  need_pip ziglang==0.13.0.post1
  need_program x86_64-w64-mingw32-gcc gcc-mingw-w64-x86-64
  need_program aarch64-linux-gnu-gcc gcc-aarch64-linux-gnu
  need_program qemu-aarch64 qemu-user
  need_program dpkg-source dpkg-dev
  need_program llvm-objdump llvm
fi
# ---- the tests' installs: add one line per need here, e.g. -------------------------------------------
#   need_apt gcc-mingw-w64-x86-64
#   need_pip some-package
#   need_cargo some-program=some-crate@1.2.3
if [ "$PURPOSE" = test ]; then
  EXTRAS="[test]" # pytest, pytest-timeout, libcosimpy (pyproject.toml)
  need_apt pkg-config libcriterion-dev # the C unit tests (Criterion, found with pkg-config)
  need_apt valgrind # the memory check of the FMU binary (ctest)
  need_cargo fmi-sim=fmi-sim@0.7.0 # the Rust FMI simulator: the second importer of the Model Exchange and FMI 3.0 tests
  need_apt clang libclang-rt-14-dev # clang with libFuzzer and the sanitizers: the fuzz harness (tests/fuzz)
  need_apt locales # the locales the locale tests run in (tests/test_text.c, fmu-test/test_locale.py):
  LOCALES+=(de_DE ps_AF) # a decimal comma; U+066B, a two-byte decimal separator
  need_program valgrind valgrind
  need_program clang clang
  need_program pkg-config pkg-config
fi
# ------------------------------------------------------------------------------------------------------
RUST_MIN=1.85 # fmi-sim 0.7 is written in Rust's edition 2024

if [ -n "$LIST" ]; then
  echo "apt: ${APT_PKGS[*]}" >&3
  echo "pip: ${PIP_PKGS[*]} vibroimpact$EXTRAS (editable, from this checkout)" >&3
  echo "cargo: ${CARGO_PKGS[*]}" >&3
  echo "locales: ${LOCALES[*]}" >&3
  exit 0
fi
# say why: the purpose of what is installed
case $PURPOSE in
  main) FOR="" ;;
  example) FOR=" (for the example)" ;;
  release) FOR=" (for the release)" ;;
  test) FOR=" (for the tests)" ;;
esac
do_it() { # <for whom> <what> <command...>: say it and run it, or say what would run (--dry-run)
  local for=$1 what=$2
  shift 2
  if [ -n "$DRY" ]; then echo "setup$for: would $what" >&2; else echo "setup$for: $what" >&2; "$@"; fi
}

# ---- apt ----------------------------------------------------------------------------------------------
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
APT_UPDATED=""
apt_install() { # <for whom> <packages...>
  local for=$1 missing=() p
  shift
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  if [ -z "$APT_UPDATED" ] && [ -z "$DRY" ]; then
    $SUDO apt-get update -qq
    APT_UPDATED=1
  fi
  do_it "$for" "apt-get install ${missing[*]}" $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
    --no-install-recommends "${missing[@]}" >/dev/null
}

# ---- Rust (the tests' fmi-sim) ------------------------------------------------------------------------
# version_at_least <version> <minimum>: sort -V orders them
version_at_least() { [ "$(printf '%s\n%s\n' "$2" "$1" | sort -V | head -n 1)" = "$2" ]; }
RUST_FROM="" # apt or rustup, when cargo is needed and missing or too old
CARGO=cargo
if [ ${#CARGO_PKGS[@]} -gt 0 ]; then
  need=""
  for entry in "${CARGO_PKGS[@]}"; do command -v "${entry%%=*}" >/dev/null || need=1; done
  have=$(rustc --version 2>/dev/null | cut -d' ' -f2 || true)
  if [ -n "$need" ] && ! { command -v cargo >/dev/null && version_at_least "${have:-0}" "$RUST_MIN"; }; then
    debian=$(apt-cache policy rustc 2>/dev/null | sed -n 's/^ *Candidate: \([0-9.]*\).*/\1/p')
    if [ -n "$debian" ] && version_at_least "$debian" "$RUST_MIN"; then
      RUST_FROM=apt
      APT_PKGS+=(cargo rustc)
    else
      RUST_FROM=rustup
      CARGO=$HOME/.cargo/bin/cargo # before an older cargo on the PATH
      echo "setup$FOR: fmi-sim needs Rust $RUST_MIN or later (edition 2024); ${have:+the rustc on the PATH is $have and }Debian's is ${debian:-not available}: Rust comes from rustup"
      APT_PKGS+=(curl ca-certificates)
    fi
  fi
fi
apt_install "" "${APT_PKGS[@]:0:N_APT_MAIN}"
apt_install "$FOR" "${APT_PKGS[@]:N_APT_MAIN}"

# ---- locales ------------------------------------------------------------------------------------------
for loc in "${LOCALES[@]}"; do
  if ! locale -a 2>/dev/null | grep -qix "$loc\.utf-\?8"; then
    do_it "$FOR" "localedef -i $loc -f UTF-8 $loc.UTF-8" $SUDO localedef -i "$loc" -f UTF-8 "$loc.UTF-8"
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
      apt_install "" "$pkg"
    fi
    if [ -n "$DRY" ]; then
      echo "setup: would make the virtual environment .venv/ from $BASE and pip install everything into it"
      echo "$PY" >&3
      exit 0
    fi
    echo "setup: $BASE does not take pip installs; making the virtual environment .venv/ (run everything with $PY)"
    rm -rf "$ROOT/.venv"
    "$BASE" -m venv "$ROOT/.venv"
  fi
fi

# ---- pip ----------------------------------------------------------------------------------------------
PIP=("$PY" -m pip install --quiet --disable-pip-version-check)
[ "$(id -u)" -ne 0 ] || PIP+=(--root-user-action=ignore)
pip_install() { # <for whom> <packages...>: those not installed (at the version given with ==)
  local for=$1 missing=() p want have
  shift
  for p in "$@"; do
    want=${p#*==}
    [ "$want" != "$p" ] || want=""
    have=$("$PY" -c "import importlib.metadata as m, sys; print(m.version(sys.argv[1]))" "${p%%[<>=!~;[]*}" 2>/dev/null) \
      && { [ -z "$want" ] || [ "$have" = "$want" ]; } || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] || do_it "$for" "pip install ${missing[*]}" "${PIP[@]}" "${missing[@]}"
}
pip_install "" "${PIP_PKGS[@]:0:N_PIP_MAIN}"
pip_install "$FOR" "${PIP_PKGS[@]:N_PIP_MAIN}"
# the package, editable, unless it is installed from this checkout since pyproject.toml last changed and
# every requirement it declares for this purpose (its extras' too: EXTRAS) is there
if ! "$PY" - "$ROOT" "$EXTRAS" <<'EOF' 2>/dev/null; then
import importlib.metadata as m, json, os, pathlib, re, sys
root, extras = pathlib.Path(sys.argv[1]).resolve(), set(re.findall(r"\w+", sys.argv[2]))
d = m.distribution("vibroimpact")
url = [f for f in d.files if f.name == "direct_url.json"][0]
info = json.loads(url.read_text())
assert info.get("dir_info", {}).get("editable") and info["url"] == root.as_uri()
assert os.path.getmtime(d.locate_file(url)) >= os.path.getmtime(root / "pyproject.toml")
for r in d.requires or []:
    extra = re.search(r"""extra\s*==\s*["']([^"']+)["']""", r)
    if extra is None or extra.group(1) in extras:
        m.distribution(re.match(r"[A-Za-z0-9._-]+", r).group(0))
EOF
  do_it "${EXTRAS:+$FOR}" "pip install -e .$EXTRAS (the vibroimpact package of this checkout)" \
    "${PIP[@]}" --no-build-isolation -e "$ROOT$EXTRAS"
fi

# ---- cargo --------------------------------------------------------------------------------------------
if [ "$RUST_FROM" = rustup ]; then
  do_it "$FOR" "rustup (a minimal current Rust toolchain) into ~/.cargo" \
    sh -c "curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --quiet --profile minimal --no-modify-path >/dev/null"
fi
for entry in "${CARGO_PKGS[@]}"; do
  program=${entry%%=*} crate=${entry#*=}
  if ! command -v "$program" >/dev/null; then
    do_it "$FOR" "cargo install $crate" "$CARGO" install --quiet --locked "$crate"
  fi
done

# ---- what must be there now ---------------------------------------------------------------------------
if [ -z "$DRY" ]; then
  missing=()
  for program in "${!PROGRAMS[@]}" "${CARGO_PKGS[@]%%=*}"; do
    command -v "$program" >/dev/null || missing+=("$program (${PROGRAMS[$program]:-cargo install})")
  done
  for loc in "${LOCALES[@]}"; do
    locale -a 2>/dev/null | grep -qix "$loc\.utf-\?8" || missing+=("the locale $loc.UTF-8 (localedef)")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "setup$FOR: not installed: ${missing[*]}"
    exit 1
  fi
fi
echo "$PY" >&3
