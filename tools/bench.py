#!/usr/bin/env python3
"""Speed against accuracy: every scenario through fmpy's simulate_fmu at several tolerances.

Usage: python3 tools/bench.py [--repeat N]      (prints a markdown table; figures, not a test)

For each scenario and rtol: the wall time of simulate_fmu over 0.1 s with output every 20 us (the
reference's grid), best of N runs (default 3), fmpy's extraction, instantiation and 5000 doSteps
included; and the accuracy: how long the FMU stays within 0.1 um of the committed rtol-1e-11
reference trace (fmu-test/reference/data). A final-time error would mean nothing for chaotic runs.
The last row repeats the timing with one output every 10 ms (10 doSteps), which leaves mostly the
integration itself.
"""
import pathlib
import sys
import time

from fmpy import simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "fmu-test"))
from compare_reference import FMU, SCENARIOS, STOP_TIME, horizon, read_trace  # noqa: E402

RTOLS = [1e-6, 1e-8, 1e-11]


def run(params, rtol, t=None, interval=None):
    return simulate_fmu(str(FMU), start_values=params, stop_time=STOP_TIME,
                        output_interval=interval or t[1] - t[0], relative_tolerance=rtol, output=["y"])


def main(repeat):
    print("| scenario | " + " | ".join(f"rtol {r:g}: wall [ms] / within 0.1 um until [ms]" for r in RTOLS) + " |")
    print("|---|" + "---|" * len(RTOLS))
    total, coarse = dict.fromkeys(RTOLS, 0.0), dict.fromkeys(RTOLS, 0.0)
    for name, scenario in SCENARIOS.items():
        ref = read_trace(name)
        cells = []
        for rtol in RTOLS:
            r = run(scenario.full, rtol, ref["time"])
            wall = min(timed(lambda: run(scenario.full, rtol, ref["time"])) for _ in range(repeat))
            until = horizon(ref["time"], ref["y"], r["y"])
            total[rtol] += wall
            coarse[rtol] += min(timed(lambda: run(scenario.full, rtol, interval=1e-2)) for _ in range(repeat))
            cells.append(f"{1e3 * wall:.0f} / {1e3 * until:.1f}")
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("| all, wall [ms] | " + " | ".join(f"{1e3 * total[r]:.0f}" for r in RTOLS) + " |")
    print("| all, output every 10 ms, wall [ms] | " + " | ".join(f"{1e3 * coarse[r]:.0f}" for r in RTOLS) + " |")


def timed(f):
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


if __name__ == "__main__":
    args = sys.argv[1:]
    main(int(args[args.index("--repeat") + 1]) if "--repeat" in args else 3)
