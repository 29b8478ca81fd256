#!/usr/bin/env bash
# Fuzzing campaigns with the libFuzzer harness of the FMU (tests/fuzz/README.md).
#
#   tools/fuzz.sh [run] [SECONDS]   build the harness, fuzz for SECONDS (default 900) from the seed
#                                   corpus and the campaign corpus build/fuzz/campaign-<FMU>/, then
#                                   minimize every new finding (build/fuzz/findings/) and print its
#                                   calls; exit status 1 when there were findings
#   tools/fuzz.sh runs N            N inputs (one process, no fork: the first finding ends it), from
#                                   the same corpora; prints the seed, the runs and the time
#   tools/fuzz.sh minimize FILE     minimize one finding (FILE.min) and print its calls
#   tools/fuzz.sh trace FILE        run one input and print every call, its arguments and status
#   tools/fuzz.sh distill           replace the seed corpus by the smallest set of the seeds and the
#                                   campaign corpus that covers the same code (keeps finding-*, crash-*)
#
# Environment: VI_BUILD_DIR (default build; configured by this script if needed), PYTHON (for the
# configure step), VI_FUZZ_FMU (default VibroImpact), VI_FUZZ_CALL_SECONDS and VI_FUZZ_HANG_SECONDS
# (the watchdog's bounds, tests/fuzz/fuzz_main.c: CPU time and wall time of one call; raise the wall
# time for a run that shares its cores at a low priority, where a call waits for the CPU),
# VI_FUZZ_SEED (libFuzzer's -seed; default a fresh one, printed, so that a run can be repeated),
# VI_FUZZ_OFF (properties to leave out, comma-separated: call-order, restore; tests/fuzz/order.c).
# One fuzzing process: the machine's other cores stay free.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BUILD=${VI_BUILD_DIR:-build}
FMU=${VI_FUZZ_FMU:-VibroImpact}
SEEDS=$ROOT/tests/fuzz/corpus/$FMU
FINDINGS=$BUILD/fuzz/findings
BIN=$BUILD/fuzz/fuzz_$FMU
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

build() {
  if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S . -B "$BUILD" -DPython3_EXECUTABLE="$(command -v "${PYTHON:-python3}")" >/dev/null
  fi
  cmake --build "$BUILD" --target vi_fuzz_harness >/dev/null
  [ -x "$BIN" ] || { echo "fuzz.sh: $BIN was not built (is VI_FUZZ on and clang's libFuzzer installed?)" >&2; exit 2; }
}

SEED=${VI_FUZZ_SEED:-$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')}

trace() { VI_FUZZ_TRACE=1 timeout 900 "$BIN" -runs=1 "$1" 2>&1 | grep -a -v '^INFO:' || true; }

minimize() {
  local crash=$1 out=$1.min
  # bounded: an input with slow calls makes every attempt slow
  timeout 600 "$BIN" -minimize_crash=1 -max_total_time=120 -exact_artifact_path="$out" "$crash" >/dev/null 2>&1 || true
  [ -s "$out" ] || cp "$crash" "$out"
  echo "== $out ($(stat -c %s "$out") bytes; $(stat -c %s "$crash") before):"
  trace "$out" | grep -a -E '^\[|^    |FINDING|ERROR|SUMMARY|^#[0-9]+ ' | head -80
}

cmd=${1:-run}
case $cmd in
  run|[0-9]*)
    [ "$cmd" = run ] && shift || true
    seconds=${1:-900}
    build
    work=$BUILD/fuzz/campaign-$FMU
    mkdir -p "$work" "$FINDINGS"
    before=$(ls "$FINDINGS" | grep -v '\.min$' | sort || true)
    echo "fuzz.sh: $seconds s of $BIN, seed $SEED; corpus $work + $SEEDS; findings in $FINDINGS"
    # -fork=1: a finding does not end the campaign; each is saved and the fuzzing goes on
    "$BIN" -seed="$SEED" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -max_total_time="$seconds" -timeout=600 \
      -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$FINDINGS/" "$work" "$SEEDS" 2>&1 |
      grep -a -E '^#[0-9]+: cov|FINDING|ERROR|SUMMARY|slowest|INFO: fuzzed' || true
    after=$(ls "$FINDINGS" | grep -v '\.min$' | sort || true)
    new=$(comm -13 <(echo "$before") <(echo "$after") | grep -v '^$' || true)
    if [ -z "$new" ]; then
      echo "fuzz.sh: no findings in $seconds s"
      exit 0
    fi
    echo "fuzz.sh: $(echo "$new" | wc -l) new findings"
    for f in $new; do minimize "$FINDINGS/$f"; done
    exit 1
    ;;
  runs)
    n=${2:?fuzz.sh runs N}
    build
    work=$BUILD/fuzz/campaign-$FMU
    mkdir -p "$work" "$FINDINGS"
    echo "fuzz.sh: $n runs of $BIN, seed $SEED; corpus $work + $SEEDS; findings in $FINDINGS"
    start=$(date +%s)
    set +e
    "$BIN" -seed="$SEED" -runs="$n" -timeout=600 -rss_limit_mb=4096 -print_final_stats=1 \
      -artifact_prefix="$FINDINGS/" "$work" "$SEEDS" >"$BUILD/fuzz/runs.log" 2>&1
    rc=$?
    set -e
    grep -a -E 'FINDING|ERROR|SUMMARY|slowest|stat::number_of_executed_units|DONE' "$BUILD/fuzz/runs.log" || true
    echo "fuzz.sh: seed $SEED, $(($(date +%s) - start)) s, exit status $rc (log: $BUILD/fuzz/runs.log)"
    exit $rc
    ;;
  minimize) build; minimize "$2" ;;
  trace) build; trace "$2" ;;
  distill)
    build
    work=$BUILD/fuzz/campaign-$FMU
    mkdir -p "$work"
    tmp=$(mktemp -d)
    "$BIN" -set_cover_merge=1 -use_counters=0 -use_cmp=0 "$tmp" "$SEEDS" "$work" >/dev/null 2>&1
    find "$SEEDS" -type f ! -name 'finding-*' ! -name 'crash-*' -delete
    cp "$tmp"/* "$SEEDS"/
    rm -rf "$tmp"
    echo "fuzz.sh: $SEEDS: $(ls "$SEEDS" | wc -l) files, $(du -sh --apparent-size "$SEEDS" | cut -f1)"
    ;;
  *) sed -n '2,23p' "$0"; exit 2 ;;
esac
