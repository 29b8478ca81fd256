"""Wall time of a 200-point sweep: in one process without Dask (the baseline), then on a Dask
LocalCluster of 1, 2 and all cores. Prints a Markdown table.

  vibroimpact bench-sweep [--points 200] [--repeat 2] [--stop-time 0.1] [--step 1e-5]

The sweep: Hertz, a = 0.1 mm, f from 100 to 600 Hz (the paper's data; most points bounce), each
point 0.1 s with a 10 us communication step. Times are the best of --repeat runs; the cluster's
start-up is timed apart. "Cores kept busy" is the workers' CPU time (time.process_time on each
worker, through Client.run) over the wall time: on a machine shared with other jobs it shows how
much of the cluster the sweep actually got, and the wall times move by 10 % or more between runs.
"""
import argparse
import os
import time

from ..fmu import fmu_path
from ..sweep import engine, spec
from ..sweep.bench import baseline, make_sweep, on_cluster


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact bench-sweep", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--points", type=int, default=200, help="grid points (default 200)")
    p.add_argument("--repeat", type=int, default=2, help="runs of each configuration; the best counts (default 2)")
    p.add_argument("--stop-time", type=float, default=0.1, help="run length per point [s] (default 0.1)")
    p.add_argument("--step", type=float, default=1e-5, help="communication step [s] (default 1e-5)")
    args = p.parse_args(argv)
    if args.points < 1 or args.repeat < 1:
        p.error("--points and --repeat are at least 1")
    fmu = str(fmu_path())
    interface = spec.Interface(fmu)
    sweep = make_sweep(interface, args.points, args.stop_time, args.step)
    spec.check(sweep, interface)
    cores = os.cpu_count()
    rows = []
    best, ref = min(baseline(fmu, sweep, interface) for _ in range(args.repeat))[0], None
    rows.append(("one process, no Dask", "-", best))
    for workers in sorted({1, 2, cores}):
        t0 = time.perf_counter()
        with engine.connect(workers=workers) as client:
            startup = time.perf_counter() - t0
            times, res = on_cluster(client, fmu, sweep, interface, args.repeat)
            failed = sum(r["status"] != "ok" for _, r in res)
            ref = ref or [r["F_max"] for _, r in res]
            same = "yes" if [r["F_max"] for _, r in res] == ref else "NO"
        label = f"LocalCluster, {workers} worker{'s' if workers > 1 else ''}" + (" (all cores)" if workers == cores else "")
        wall, cpu = min(times)
        rows.append((label, f"{startup:.1f}", wall, failed, same, cpu))
    load = os.getloadavg()[0]
    print(f"{args.points}-point sweep (Hertz, a = 0.1 mm, f = 100..600 Hz, {args.stop_time:g} s per point, "
          f"step {args.step:g} s), best of {args.repeat}, {cores} cores, load average {load:.1f} at the end\n")
    print("| run | cluster start [s] | sweep wall [s] | points/s | speed-up vs 1 worker | worker CPU [s] | "
          "cores kept busy | failed | same F_max as 1 worker |")
    print("|---|---|---|---|---|---|---|---|---|")
    one = next(r[2] for r in rows if r[0].startswith("LocalCluster, 1 "))
    for r in rows:
        failed, same, cpu = r[3:] if len(r) > 3 else ("-", "-", None)
        busy = f"{cpu:.1f} | {cpu / r[2]:.2f}" if cpu is not None else "- | -"
        print(f"| {r[0]} | {r[1]} | {r[2]:.2f} | {args.points / r[2]:.1f} | {one / r[2]:.2f} | {busy} | {failed} | {same} |")
