#!/usr/bin/env bash
# The release FMUs, made on a Debian machine (x86_64):
#   dist/fmi2/VibroImpact.fmu, Track.fmu, Vehicle.fmu   binaries/linux64, win64 and darwin64
#   dist/fmi3/*.fmu                                    x86_64-linux, x86_64-windows, aarch64-linux,
#                                                      x86_64-darwin, aarch64-darwin
#                                                      (when the sources build FMI 3.0 FMUs; else skipped)
# each also a source FMU (sources/: cmake/vi_fmu_sources.py), the aarch64 Linux libraries (FMI 2.0
# names no platform for them) in build/release/aarch64-linux/, and
#   dist/vibroimpact-<version>-py3-none-any.whl        the Python package with the VibroImpact FMUs
#                                                      above inside: installs with no compiler
#                                                      (tools/release_wheel.py)
# Each FMU carries its documentation/ page, its licences (documentation/licenses/) and the release version
# and date in its model description (SOURCE_DATE_EPOCH: below).
#
# One build (CMakeLists.txt, vi_add_fmu in cmake/vi_fmu.cmake; Release, warnings are errors, the FMU
# binaries stripped) per target in build/release/<target>/:
#   x86_64-windows  cmake/toolchain-x86_64-windows.cmake (mingw-w64)
#   aarch64-linux   cmake/toolchain-aarch64-linux.cmake  (gcc-aarch64-linux-gnu)
#   x86_64-linux    this machine; its FMUs also take the binaries of the others (VI_FMU_MERGE_BINARIES)
# For each cross target CVODE is built from SUNDIALS' Debian source package (apt-get source sundials,
# 6.4.1) as static libraries and kept in ${XDG_CACHE_HOME:-~/.cache}/vibroimpact/, so that the next run
# is fast; the native build links Debian's libsundials-dev (the same 6.4.1). Every build packs the
# same sources/ (-DVI_FMU_SUNDIALS_SOURCES=<the source package>).
#   macOS           no CMake build: the binaries are compiled from the sources/ of the Windows build's
#                   FMUs (tools/fmu_source_build.py) with zig cc (pip package ziglang) for x86_64 and
#                   aarch64 macOS, kept in the same cache, and packed like another build's FMUs
#                   (build/release/darwin/) for the merge
# Checked before anything is copied to dist/: the DLLs import only KERNEL32.dll and msvcrt.dll and export
# only fmi2* (fmi3*) functions; the Linux libraries need only libc and libm and export only those; the
# macOS libraries (llvm-objdump, llvm-nm) load only libSystem and export only those, the aarch64 ones
# signed (ad hoc, as macOS requires on ARM); every FMU holds the binaries of its platforms and the
# source files its model description lists, and fmpy validates it.
#
# Usage: tools/release.sh            (PYTHON: the interpreter, as for tools/setup.sh; JOBS: default nproc)
# Installs what it needs (tools/setup.sh --release: the main job's installs, then the cross compilers,
# wine64, qemu-user, dpkg-dev, llvm, zig) and, the first time, lists source packages for the Debian
# archive entry of /etc/apt/sources.list.d/debian.sources (Types: deb deb-src).
set -euo pipefail
shopt -s inherit_errexit # a failing command inside $(...) fails it (the checks below run in $(...))
cd "$(dirname "$0")/.."
ROOT=$PWD
JOBS=${JOBS:-$(nproc)}
SUNDIALS_VERSION=6.4.1
CACHE=${XDG_CACHE_HOME:-$HOME/.cache}/vibroimpact
BUILD=$ROOT/build/release
CROSS_TARGETS=(x86_64-windows aarch64-linux)
NATIVE=x86_64-linux
FMUS=(VibroImpact Track Vehicle) # LayerTest (the generic layer's test model) is not released
# --- macOS binaries (zig cc, the pip package ziglang that tools/setup.sh --release installs) ---
DARWIN_TARGETS=(x86_64-darwin aarch64-darwin)
declare -A ZIG_TARGET=([x86_64-darwin]=x86_64-macos [aarch64-darwin]=aarch64-macos)
# --- end macOS binaries ---
DEB_SOURCES=/etc/apt/sources.list.d/debian.sources

die() { echo "release: $*" >&2; exit 1; }
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO=sudo

[ "$(uname -m)" = x86_64 ] || die "the release is made on an x86_64 Debian machine (this is $(uname -m))"

# --- the release's version and date (cmake/vi_fmu_stamp.py) -----------------------------------------------
# Every build stamps the same generationDateAndTime into the model descriptions (the native FMUs take the
# other builds' binaries only where their modelDescription.xml is the same file): SOURCE_DATE_EPOCH when
# given, else the time of the last commit (a reproducible release), else now, fixed once for all builds.
SOURCE_DATE_EPOCH=${SOURCE_DATE_EPOCH:-$(git -C "$ROOT" log -1 --format=%ct 2>/dev/null || date +%s)}
export SOURCE_DATE_EPOCH
# --- end of the release's version and date ---------------------------------------------------------------

# --- what the builds need: tools/setup.sh --release ----------------------------------------------------
PYTHON=$(./tools/setup.sh --release) # the interpreter with fmpy (from $PYTHON, or the .venv/ setup makes)
# --- macOS binaries ---
# zig's version, in the cache key of the macOS binaries
RELEASE_PIP_PKGS=("ziglang==$("$PYTHON" -c 'import importlib.metadata as m; print(m.version("ziglang"))')")
# --- end macOS binaries ---

# --- SUNDIALS' Debian source package -----------------------------------------------------------------
sundials_src() { ls -d "$CACHE"/src/sundials-"$SUNDIALS_VERSION"*/ 2>/dev/null | head -n 1; }
if [ -z "$(sundials_src)" ]; then
  if ! apt-get source --print-uris -qq sundials >/dev/null 2>&1; then
    # List source packages too in the entry of the Debian archive (not the security archive).
    [ -f "$DEB_SOURCES" ] || die "$DEB_SOURCES not found: list a deb-src entry for the Debian archive by hand"
    echo "release: $DEB_SOURCES: Types: deb deb-src for the Debian archive; apt-get update"
    tmp=$(mktemp)
    awk 'BEGIN { RS = "" }
         !done && !/debian-security/ {
           n = split($0, line, "\n"); out = ""
           for (i = 1; i <= n; i++) {
             if (line[i] == "Types: deb") { line[i] = "Types: deb deb-src"; done = 1 }
             out = out (i > 1 ? "\n" : "") line[i]
           }
           $0 = out
         }
         { printf "%s%s", (NR > 1 ? "\n\n" : ""), $0 }
         END { print "" }' "$DEB_SOURCES" >"$tmp"
    grep -q '^Types: deb deb-src$' "$tmp" || die "no 'Types: deb' entry for the Debian archive in $DEB_SOURCES"
    $SUDO cp "$tmp" "$DEB_SOURCES"
    rm -f "$tmp"
    $SUDO apt-get update -qq
  fi
  echo "release: apt-get source sundials (into $CACHE/src)"
  mkdir -p "$CACHE/src"
  (cd "$CACHE/src" && apt-get source -qq sundials >/dev/null 2>&1) || die "apt-get source sundials failed"
  [ -n "$(sundials_src)" ] || die "apt-get source sundials did not give SUNDIALS $SUNDIALS_VERSION: $(ls "$CACHE/src")"
fi
SUNDIALS_SRC=$(sundials_src)

# --- CVODE for each cross target: static libraries, nothing else --------------------------------------
# The cached build is used when it was made from the same toolchain file with the same options.
SUNDIALS_OPTIONS=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_LIBDIR=lib
  -DCMAKE_POSITION_INDEPENDENT_CODE=ON -DBUILD_SHARED_LIBS=OFF -DBUILD_STATIC_LIBS=ON
  -DBUILD_CVODE=ON -DBUILD_CVODES=OFF -DBUILD_ARKODE=OFF -DBUILD_IDA=OFF -DBUILD_IDAS=OFF -DBUILD_KINSOL=OFF
  -DBUILD_FORTRAN_MODULE_INTERFACE=OFF -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_CXX=OFF -DEXAMPLES_INSTALL=OFF
  -DBUILD_TESTING=OFF -DENABLE_MPI=OFF -DENABLE_OPENMP=OFF -DENABLE_PTHREAD=OFF -DSUNDIALS_INDEX_SIZE=64)
sundials_prefix() { echo "$CACHE/sundials-$SUNDIALS_VERSION-$1"; }
for target in "${CROSS_TARGETS[@]}"; do
  prefix=$(sundials_prefix "$target")
  toolchain="$ROOT/cmake/toolchain-$target.cmake"
  key=$({ basename "$SUNDIALS_SRC"; cat "$toolchain"; echo "${SUNDIALS_OPTIONS[*]}"; } | sha256sum | cut -c1-16)
  [ -f "$prefix/lib/cmake/sundials/SUNDIALSConfig.cmake" ] && [ "$(cat "$prefix/build-key" 2>/dev/null)" = "$key" ] && continue
  echo "release: SUNDIALS $SUNDIALS_VERSION (CVODE, static) for $target into $prefix"
  work="$CACHE/build-sundials-$target"
  rm -rf "$work" "$prefix.partial" "$prefix"
  cmake -S "$SUNDIALS_SRC" -B "$work" -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DCMAKE_INSTALL_PREFIX="$prefix.partial" \
    "${SUNDIALS_OPTIONS[@]}" >"$work.log" 2>&1 \
    || { tail -n 30 "$work.log"; die "SUNDIALS configure for $target failed ($work.log)"; }
  cmake --build "$work" -j"$JOBS" >>"$work.log" 2>&1 || { tail -n 30 "$work.log"; die "SUNDIALS build for $target failed ($work.log)"; }
  cmake --install "$work" >>"$work.log" 2>&1 || die "SUNDIALS install for $target failed ($work.log)"
  echo "$key" >"$prefix.partial/build-key"
  mv "$prefix.partial" "$prefix"
  rm -rf "$work" "$work.log"
done

# --- the FMUs: cross targets first, then this machine's, which packs the others' binaries too --------
configure_and_build() { # <target> <cmake arguments...>
  local target=$1 dir="$BUILD/$1" log="$BUILD/$1.log"
  shift
  mkdir -p "$BUILD"
  cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DVI_WERROR=ON -DPython3_EXECUTABLE="$PYTHON" \
    -DCMAKE_SHARED_LINKER_FLAGS=-s -DVI_FMU_SUNDIALS_SOURCES="$SUNDIALS_SRC" "$@" >"$log" 2>&1 \
    || { tail -n 30 "$log"; die "configure for $target failed ($log)"; }
  cmake --build "$dir" -j"$JOBS" --target "${FMUS[@]}" fmu_driver fmu3_driver LayerTest >>"$log" 2>&1 \
    || { tail -n 40 "$log"; die "build for $target failed ($log)"; }
  # the FMUs (where FMI 2.0 names the platform; and FMI 3.0 ones when the sources make them)
  local help fmu_targets
  help=$(cmake --build "$dir" --target help 2>>"$log") || die "cmake --build $dir --target help failed ($log)"
  fmu_targets=$(sed -n 's/^\.\.\. \([A-Za-z0-9_]*_fmu[0-9]*\)$/\1/p; s/^\([A-Za-z0-9_]*_fmu[0-9]*\): phony$/\1/p' <<<"$help" \
                | grep -v '^LayerTest_' || true) # grep: no FMU target left is no error
  if [ -n "$fmu_targets" ]; then
    # shellcheck disable=SC2086
    cmake --build "$dir" -j"$JOBS" --target $fmu_targets >>"$log" 2>&1 \
      || { tail -n 40 "$log"; die "packing the FMUs for $target failed ($log)"; }
  fi
}
merge=()
for target in "${CROSS_TARGETS[@]}"; do
  configure_and_build "$target" -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/toolchain-$target.cmake" \
    -DSUNDIALS_DIR="$(sundials_prefix "$target")/lib/cmake/sundials"
  merge+=("$BUILD/$target")
done
# --- macOS binaries ---
# darwin_fmu <FMU with sources/> <its place in a build> <targets...>: the FMU's binaries for the
# targets, compiled from its sources/ alone (cached under a key of the sources, the compiler and the
# tool), packed as build/release/darwin/<place> (modelDescription.xml and binaries/) for the merge
darwin_fmu() {
  local fmu=$1 place=$2 out="$BUILD/darwin.stage/$2" key target cached
  shift 2
  rm -rf "$out"
  mkdir -p "$out" "$(dirname "$BUILD/darwin/$place")"
  for target in "$@"; do
    key=$({ "$PYTHON" - "$fmu" <<'EOF'
import hashlib, sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
for n in sorted(z.namelist()):
    if n == "modelDescription.xml" or n.startswith("sources/"):
        print(n, hashlib.sha256(z.read(n)).hexdigest())
EOF
      echo "$target ${RELEASE_PIP_PKGS[*]}"; cat "$ROOT/tools/fmu_source_build.py"; } | sha256sum | cut -c1-16)
    cached="$CACHE/darwin/$key"
    if ! [ -d "$cached" ]; then
      echo "release: $(basename "$fmu") (FMI $([ "${place#fmi3/}" = "$place" ] && echo 2.0 || echo 3.0)) for $target from its sources (zig cc) into $cached"
      rm -rf "$cached.partial"
      "$PYTHON" "$ROOT/tools/fmu_source_build.py" cc "$fmu" "$cached.partial" --target "$target" \
        -- "$PYTHON" -m ziglang cc -target "${ZIG_TARGET[$target]}" >/dev/null || die "the $target build of $fmu failed"
      mv "$cached.partial" "$cached"
    fi
    cp -r "$cached/." "$out/"
    DARWIN_USED+=("$key")
  done
  rm -f "$BUILD/darwin/$place"
  (cd "$out" && cmake -E tar cf "$BUILD/darwin/$place" --format=zip modelDescription.xml binaries)
}
rm -rf "$BUILD/darwin" "$BUILD/darwin.stage"
DARWIN_USED=() # the cache entries of this run; the others (older sources) are deleted below
for fmu in "${FMUS[@]}"; do
  darwin_fmu "$BUILD/x86_64-windows/$fmu.fmu" "$fmu.fmu" x86_64-darwin
  if [ -f "$BUILD/x86_64-windows/fmi3/$fmu.fmu" ]; then
    darwin_fmu "$BUILD/x86_64-windows/fmi3/$fmu.fmu" "fmi3/$fmu.fmu" "${DARWIN_TARGETS[@]}"
  fi
done
for entry in "$CACHE"/darwin/*; do
  [[ " ${DARWIN_USED[*]} " == *" $(basename "$entry") "* ]] || rm -rf "$entry"
done
merge+=("$BUILD/darwin")
# --- end macOS binaries ---
configure_and_build "$NATIVE" -DVI_FMU_MERGE_BINARIES="$(IFS=';'; echo "${merge[*]}")"

# --- checks of every binary ------------------------------------------------------------------------
check_pe() { # <dll> [<prefix>]: imports only Windows system DLLs, exports only <prefix>* (fmi2) functions
  local dll=$1 prefix=${2:-fmi2} imports exports
  [ -f "$dll" ] || die "$dll was not built"
  imports=$(x86_64-w64-mingw32-objdump -p "$dll" | sed -n 's/^\s*DLL Name: //p' | sort -u | tr '\n' ' ')
  for i in $imports; do
    case "${i,,}" in kernel32.dll | msvcrt.dll) ;; *) die "$dll imports $i (only KERNEL32.dll and msvcrt.dll allowed)" ;; esac
  done
  exports=$(x86_64-w64-mingw32-objdump -p "$dll" | awk '/\[Ordinal\/Name Pointer\] Table/ { on = 1; next } on && /^[ \t]*\[/ { print $NF; next } on { on = 0 }')
  [ -n "$exports" ] || die "$dll exports nothing"
  if grep -qv "^$prefix" <<<"$exports"; then die "$dll exports more than $prefix*: $(grep -v "^$prefix" <<<"$exports" | tr '\n' ' ')"; fi
  echo "imports ${imports% }; exports $(wc -l <<<"$exports") $prefix* functions"
}
check_elf() { # <so> [<prefix>]: needs only libc and libm, exports only <prefix>* (fmi2) functions
  local so=$1 prefix=${2:-fmi2} needed exports
  [ -f "$so" ] || die "$so was not built"
  needed=$(readelf -dW "$so" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | tr '\n' ' ')
  for n in $needed; do
    case "$n" in libc.so.6 | libm.so.6) ;; *) die "$so needs $n (only libc.so.6 and libm.so.6 allowed)" ;; esac
  done
  exports=$(readelf -W --dyn-syms "$so" | awk '$5 == "GLOBAL" && $7 != "UND" && ($4 == "FUNC" || $4 == "OBJECT") { sub(/@.*/, "", $8); print $8 }')
  [ -n "$exports" ] || die "$so exports nothing"
  if grep -qv "^$prefix" <<<"$exports"; then die "$so exports more than $prefix*: $(grep -v "^$prefix" <<<"$exports" | tr '\n' ' ')"; fi
  echo "needs ${needed% }; exports $(wc -l <<<"$exports") $prefix* functions"
}
# --- macOS binaries ---
check_macho() { # <dylib> <prefix> <arch>: loads only libSystem, exports only <prefix>* functions; ARM64: signed
  local lib=$1 prefix=$2 arch=$3 used exports minos
  [ -f "$lib" ] || die "$lib was not built"
  command -v llvm-objdump >/dev/null && command -v llvm-nm >/dev/null || die "llvm-objdump or llvm-nm not found (Debian package llvm)"
  llvm-objdump --macho --private-header "$lib" | grep -q "MH_MAGIC_64 *$arch .* DYLIB" || die "$lib is no $arch Mach-O library"
  used=$(llvm-objdump --macho --dylibs-used "$lib" | sed -n 's/^\s*\(\S*\) (compatibility.*/\1/p' \
         | grep -vx "@rpath/$(basename "$lib")" | tr '\n' ' ')
  [ "$used" = "/usr/lib/libSystem.B.dylib " ] || die "$lib loads $used(only /usr/lib/libSystem.B.dylib allowed)"
  exports=$(llvm-nm -gU "$lib" | awk '{ print $3 }')
  [ -n "$exports" ] || die "$lib exports nothing"
  if grep -qv "^_$prefix" <<<"$exports"; then die "$lib exports more than $prefix*: $(grep -v "^_$prefix" <<<"$exports" | tr '\n' ' ')"; fi
  if [ "$arch" = ARM64 ]; then
    llvm-objdump --macho --all-headers "$lib" | grep -q "cmd LC_CODE_SIGNATURE" || die "$lib is not signed (macOS on ARM loads only signed code)"
  fi
  minos=$(llvm-objdump --macho --all-headers "$lib" | awk '$1 == "minos" && !seen { print $2; seen = 1 }')
  echo "loads ${used% }; exports $(wc -l <<<"$exports") $prefix* functions; macOS $minos or later"
}
# --- end macOS binaries ---
declare -A CHECKED
for fmu in "${FMUS[@]}"; do
  CHECKED[$fmu.dll]=$(check_pe "$BUILD/x86_64-windows/$fmu.dll")
  CHECKED[$fmu.so]=$(check_elf "$BUILD/x86_64-linux/$fmu.so")
  CHECKED[$fmu.aarch64]=$(check_elf "$BUILD/aarch64-linux/$fmu.so")
  readelf -h "$BUILD/aarch64-linux/$fmu.so" | grep -q 'Machine:.*AArch64' || die "$fmu.so for aarch64-linux is not an AArch64 library"
  CHECKED[$fmu.darwin64]=$(check_macho "$BUILD/darwin.stage/$fmu.fmu/binaries/darwin64/$fmu.dylib" fmi2 X86_64)
  if [ -f "$BUILD/$NATIVE/fmi3/$fmu.fmu" ]; then # the FMI 3.0 binaries, where the sources build them
    CHECKED[$fmu.fmi3.dll]=$(check_pe "$BUILD/x86_64-windows/fmi3/$fmu.dll" fmi3)
    CHECKED[$fmu.fmi3.so]=$(check_elf "$BUILD/x86_64-linux/fmi3/$fmu.so" fmi3)
    CHECKED[$fmu.fmi3.aarch64]=$(check_elf "$BUILD/aarch64-linux/fmi3/$fmu.so" fmi3)
    CHECKED[$fmu.fmi3.x86_64-darwin]=$(check_macho "$BUILD/darwin.stage/fmi3/$fmu.fmu/binaries/x86_64-darwin/$fmu.dylib" fmi3 X86_64)
    CHECKED[$fmu.fmi3.aarch64-darwin]=$(check_macho "$BUILD/darwin.stage/fmi3/$fmu.fmu/binaries/aarch64-darwin/$fmu.dylib" fmi3 ARM64)
  fi
done

# --- dist/ ------------------------------------------------------------------------------------------
fmu_platforms() { # <fmu>: the binaries/<platform>/<name>.<ext> it holds, one per line
  "$PYTHON" -c 'import sys, zipfile; print("\n".join(sorted(n for n in zipfile.ZipFile(sys.argv[1]).namelist() if n.startswith("binaries/") and not n.endswith("/"))))' "$1"
}
require_binaries() { # <fmu> <expected binaries/... paths>
  local fmu=$1 have
  shift
  have=$(fmu_platforms "$fmu")
  [ "$have" = "$(printf '%s\n' "$@" | sort)" ] || die "$fmu holds $(echo "$have" | tr '\n' ' ')instead of $*"
}
require_sources() { # <fmu>: a source FMU: every file its model description lists (read by fmpy) is in sources/
  "$PYTHON" - "$1" <<'EOF' || die "$1 is no source FMU"
import sys, zipfile
from fmpy import read_model_description
names = zipfile.ZipFile(sys.argv[1]).namelist()
configs = read_model_description(sys.argv[1]).buildConfigurations
files = [f for c in configs for s in c.sourceFileSets for f in s.sourceFiles]
missing = [f for f in files if "sources/" + f not in names]
if not files or missing:
    sys.exit(f"release: {sys.argv[1]}: " + ("no source files listed" if not files else "missing " + " ".join(missing)))
EOF
}
validate() { # <fmu...>: fmpy's validation of the model description
  "$PYTHON" - "$@" <<'EOF' || die "fmpy does not validate the release FMUs"
import sys
from fmpy.validation import validate_fmu
bad = 0
for path in sys.argv[1:]:
    problems = validate_fmu(path)
    for p in problems:
        print(f"release: {path}: {p}", file=sys.stderr)
    bad += len(problems)
sys.exit(1 if bad else 0)
EOF
}

rm -rf "$ROOT/dist/fmi2" "$ROOT/dist/fmi3"
mkdir -p "$ROOT/dist/fmi2"
for fmu in "${FMUS[@]}"; do
  src="$BUILD/$NATIVE/$fmu.fmu"
  require_binaries "$src" "binaries/linux64/$fmu.so" "binaries/win64/$fmu.dll" "binaries/darwin64/$fmu.dylib"
  require_sources "$src"
  cp "$src" "$ROOT/dist/fmi2/"
done
validate "$ROOT"/dist/fmi2/*.fmu
fmi3_note="skipped: the sources build no FMI 3.0 FMU (no $BUILD/$NATIVE/fmi3/*.fmu)"
if ls "$BUILD/$NATIVE"/fmi3/*.fmu >/dev/null 2>&1; then
  mkdir -p "$ROOT/dist/fmi3"
  for fmu in "${FMUS[@]}"; do
    src="$BUILD/$NATIVE/fmi3/$fmu.fmu"
    [ -f "$src" ] || die "$src missing (the FMI 3.0 build makes other FMUs than ${FMUS[*]})"
    require_binaries "$src" "binaries/aarch64-linux/$fmu.so" "binaries/x86_64-linux/$fmu.so" "binaries/x86_64-windows/$fmu.dll" \
      "binaries/aarch64-darwin/$fmu.dylib" "binaries/x86_64-darwin/$fmu.dylib"
    require_sources "$src"
    cp "$src" "$ROOT/dist/fmi3/"
  done
  validate "$ROOT"/dist/fmi3/*.fmu
  fmi3_note="x86_64-linux, x86_64-windows, aarch64-linux, x86_64-darwin, aarch64-darwin"
fi

# --- the wheel ---
wheel_fmus=(vibroimpact/VibroImpact.fmu="$ROOT/dist/fmi2/VibroImpact.fmu") # where pip install . puts them
if [ -f "$ROOT/dist/fmi3/VibroImpact.fmu" ]; then wheel_fmus+=(vibroimpact/fmi3/VibroImpact.fmu="$ROOT/dist/fmi3/VibroImpact.fmu"); fi
WHEEL=$("$PYTHON" "$ROOT/tools/release_wheel.py" "$ROOT/dist" "${wheel_fmus[@]}") || die "the wheel was not built"
# --- end the wheel ---

# --- what was made -----------------------------------------------------------------------------------
size() { stat -c %s "$1"; }
echo "release: SUNDIALS $SUNDIALS_VERSION (Debian source $(basename "$SUNDIALS_SRC")) for ${CROSS_TARGETS[*]}: $CACHE"
printf '%-36s %10s  %s\n' "file" "bytes" "contents / checks"
for f in "$ROOT"/dist/fmi2/*.fmu "$ROOT"/dist/fmi3/*.fmu; do
  [ -f "$f" ] || continue
  printf '%-36s %10s  %s\n' "${f#"$ROOT"/}" "$(size "$f")" "$(fmu_platforms "$f" | sed 's|^binaries/\([^/]*\)/.*|\1|' | tr '\n' ' ')(fmpy: valid)"
done
for fmu in "${FMUS[@]}"; do
  printf '%-36s %10s  %s\n' "linux64/$fmu.so" "$(size "$BUILD/x86_64-linux/$fmu.so")" "${CHECKED[$fmu.so]}"
  printf '%-36s %10s  %s\n' "win64/$fmu.dll" "$(size "$BUILD/x86_64-windows/$fmu.dll")" "${CHECKED[$fmu.dll]}"
  printf '%-36s %10s  %s\n' "aarch64-linux/$fmu.so" "$(size "$BUILD/aarch64-linux/$fmu.so")" "${CHECKED[$fmu.aarch64]}"
  printf '%-36s %10s  %s\n' "darwin64/$fmu.dylib" "$(size "$BUILD/darwin.stage/$fmu.fmu/binaries/darwin64/$fmu.dylib")" "${CHECKED[$fmu.darwin64]}"
  [ -n "${CHECKED[$fmu.fmi3.so]:-}" ] || continue
  printf '%-36s %10s  %s\n' "fmi3 x86_64-linux/$fmu.so" "$(size "$BUILD/x86_64-linux/fmi3/$fmu.so")" "${CHECKED[$fmu.fmi3.so]}"
  printf '%-36s %10s  %s\n' "fmi3 x86_64-windows/$fmu.dll" "$(size "$BUILD/x86_64-windows/fmi3/$fmu.dll")" "${CHECKED[$fmu.fmi3.dll]}"
  printf '%-36s %10s  %s\n' "fmi3 aarch64-linux/$fmu.so" "$(size "$BUILD/aarch64-linux/fmi3/$fmu.so")" "${CHECKED[$fmu.fmi3.aarch64]}"
  for d in x86_64-darwin aarch64-darwin; do
    printf '%-36s %10s  %s\n' "fmi3 $d/$fmu.dylib" "$(size "$BUILD/darwin.stage/fmi3/$fmu.fmu/binaries/$d/$fmu.dylib")" "${CHECKED[$fmu.fmi3.$d]}"
  done
done
echo "release: dist/fmi3: $fmi3_note"
echo "release: ${WHEEL#"$ROOT"/} ($(size "$WHEEL") bytes): the Python package with dist/fmi2 and dist/fmi3 VibroImpact.fmu"
echo "release: aarch64-linux libraries (no FMI 2.0 platform): build/release/aarch64-linux/{$(IFS=,; echo "${FMUS[*]}")}.so"
