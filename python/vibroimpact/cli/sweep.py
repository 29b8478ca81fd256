"""Parameter sweeps of the VibroImpact FMU on Dask.

  vibroimpact sweep --set contact_model=hertz --set a=1e-4 --grid f=100:600:51 \\
      --stop-time 0.2 --transient 0.1 --step 1e-5 --out results/sweep-hertz

Runs the full product of the grids, one FMU instance per point (or per continuation chain) with
fmpy's FMU2Slave, on a Dask LocalCluster (--workers N, default: all cores) or on a running Dask
scheduler (--scheduler tcp://host:8786). Writes DIR/sweep.csv (one row per point: the grid values,
then F_max F_min F_mean delta_max sep_max contact_fraction n_impacts W_plastic status message),
DIR/poincare.csv (indentation and velocity once per excitation period after the transient),
DIR/sweep.json (the settings) and DIR/response.png, DIR/bifurcation.png.

--sweep-direction up|down: a continuation sweep. Along the first grid variable (which must be
tunable, e.g. the excitation a or f, or an input), each point continues from the previous point's
final state on the same instance: the new value is set at the communication point where the
previous point ended (a whole number of excitation periods, so at phase 0). One chain per
combination of the other grids; the chains run in parallel.

Before anything goes to Dask, one FMU instance here is initialized with the --set values and each
corner of the grid (each grid's first and last value): when the FMU refuses every corner, the sweep
stops with the FMU's reason; a corner it refuses is named, and the sweep runs.

Time grid and statistics: see vibroimpact/sweep/point.py (the step is shrunk to divide the excitation
period; each point runs a whole number of periods covering --stop-time). Failed points stay in the
CSV with status 'error' and the FMU's message.

Each point's rows are written as it finishes; at the end both files are put in grid order. Ctrl-C
stops the sweep and keeps the finished points; --resume (same options, same FMU) runs only the
points not yet in DIR/sweep.csv (a continuation chain runs whole unless all its points are there).

Exit code: 0 when the sweep ran, even when some points failed; 1 when every point failed (the first
reason is printed) or the cluster could not be reached; 2 for options that cannot run; 130 when
interrupted.
"""
import argparse
import os
import sys
import time

from .. import plotting
from ..failure import CommandError, out_dir
from ..fmu import ENV, fmu_path
from ..sweep import engine, spec
from ..sweep.probe import NotHere, label, probe

DPI = 110


def parse_args(argv):
    p = argparse.ArgumentParser(prog="vibroimpact sweep", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split("\n\n", 1)[1])
    p.add_argument("--fmu", default=None, help=f"the FMU (default: vibroimpact.fmu_path(): ${ENV}, the installed "
                   "package's FMU, or build/VibroImpact.fmu of a checkout)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="fixed start value (repeatable); enumerations by value or item name, e.g. contact_model=hertz")
    p.add_argument("--grid", action="append", dest="grids", default=[], type=lambda t: (t, False),
                   metavar="NAME=START:STOP:N", help="linear grid (repeatable); the full product of all grids is run")
    p.add_argument("--loggrid", action="append", dest="grids", type=lambda t: (t, True),
                   metavar="NAME=START:STOP:N", help="logarithmic grid (repeatable)")
    p.add_argument("--stop-time", type=float, default=0.1, metavar="T", help="run length per point [s] (default 0.1)")
    p.add_argument("--step", type=float, default=1e-5, metavar="H",
                   help="largest communication step [s]; statistics are sampled at each step (default 1e-5)")
    p.add_argument("--transient", type=float, default=0.0, metavar="T0",
                   help="statistics and Poincare samples over [T0, T] of each point (default 0)")
    p.add_argument("--out", default="results/sweep", metavar="DIR", help="output directory (default results/sweep)")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes of the local cluster (default: all cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="use a running Dask scheduler, e.g. tcp://host:8786, instead of a local cluster")
    p.add_argument("--connect-timeout", type=float, default=60.0, metavar="S",
                   help="with --scheduler: how long to wait for the scheduler and its first worker (default 60 s)")
    p.add_argument("--sweep-direction", choices=["up", "down"], default=None,
                   help="continuation along the first grid variable, ascending (up) or descending (down)")
    p.add_argument("--resume", action="store_true",
                   help="keep the points an earlier, interrupted run of the same sweep wrote to DIR; run the rest")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-plots", action="store_true", help="write the CSV files only")
    args = p.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        p.error("--workers must be at least 1")
    if args.workers is not None and args.scheduler:
        p.error("--workers sizes the local cluster; a --scheduler has its own workers")
    return args


def build(args, interface):
    """The Sweep the options describe, in the order the grids were given on the command line."""
    fixed = dict(spec.parse_set(interface, s) for s in args.set)
    grids = [spec.parse_grid(interface, text, log) for text, log in args.grids]  # in the order given
    log_axes = tuple(g[0] for g, (_, log) in zip(grids, args.grids) if log)
    return spec.Sweep(fixed=fixed, grids=grids, stop_time=args.stop_time, step=args.step,
                      transient=args.transient, direction=args.sweep_direction, log_axes=log_axes,
                      title=" ".join(args.set))


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    args = parse_args(argv)
    try:
        args.fmu = str(fmu_path() if args.fmu is None else args.fmu)
        open(args.fmu, "rb").close()
    except OSError as e:
        print(f"sweep: {e}", file=sys.stderr)
        return 2
    try:
        interface = spec.Interface(args.fmu)
        sweep = build(args, interface)
        spec.check(sweep, interface)
        check_corners(sweep, interface, args.fmu)
        out_dir(args.out)
        output = engine.Output(args.out, sweep, argv=["vibroimpact", "sweep"] + list(argv),
                               fmu_sha256=engine.file_sha256(args.fmu), resume=args.resume)
    except (spec.SpecError, CommandError) as e:
        print(f"sweep: {e}", file=sys.stderr)
        return 2
    return run(args, sweep, interface, output)


def check_corners(sweep, interface, fmu):
    """The probe: a SpecError when the FMU refuses every corner; a line for each corner it refuses."""
    try:
        refused = probe(sweep, interface, fmu)
    except NotHere as e:
        print(f"sweep: the FMU does not load here, so its workers alone check the values ({e})", file=sys.stderr)
        return
    for corner, reason in refused:
        print(f"sweep: the FMU refuses to initialize at {label(corner)} (those points will fail): {reason}",
              file=sys.stderr)


def run(args, sweep, interface, output):
    """The points not yet in `output` on Dask, each written as it finishes; the figures; the exit code."""
    t0, before, ran = time.perf_counter(), len(output.done), [0]

    def finished(indices, results):
        output.add(indices, results)
        ran[0] += len(indices)

    try:
        if before < len(output.points):
            engine.run(sweep, interface, args.fmu, workers=args.workers, scheduler=args.scheduler,
                       progress=not args.no_progress, connect_timeout=args.connect_timeout, done=output.done,
                       on_chain=finished)
    except KeyboardInterrupt:
        if not output.done:
            print(f"sweep: interrupted before the first point finished; {args.out} is as it was", file=sys.stderr)
            return 130
        output.finish()
        print(f"sweep: interrupted; {len(output.done)} of {len(output.points)} points are in {args.out}/sweep.csv "
              "and poincare.csv: the same command with --resume runs the rest", file=sys.stderr)
        return 130
    except (OSError, RuntimeError, TimeoutError) as e:  # no scheduler there, no worker joining, ...
        output.finish()
        print(f"sweep: {e}", file=sys.stderr)
        return 1
    output.finish()
    if not args.no_plots:
        write_figures(args.out, sweep)
    failed, n = output.failures(), len(output.points)
    wall, ran = time.perf_counter() - t0, ran[0]
    print(f"sweep: {ran} point{'' if ran == 1 else 's'} in {wall:.1f} s ({ran / wall:.1f}/s)"
          + (f", {len(output.done) - ran} kept from before" if before else "")
          + f", {len(failed)} failed -> {args.out}/sweep.csv, poincare.csv"
          + ("" if args.no_plots else ", response.png, bifurcation.png"))
    if failed and len(failed) == n:
        values, message = failed[0]
        print(f"sweep: every point failed; the first{' (' + label(values) + ')' if values else ''}: {message}",
              file=sys.stderr)
        return 1
    return 0


def write_figures(out_dir, sweep):
    """DIR/response.png and DIR/bifurcation.png of one sweep, read back from its CSV files."""
    if not sweep.grids:
        return []
    cols, poincare = engine.read(out_dir)
    return [plotting.save(plotting.response_figure(sweep, cols), os.path.join(out_dir, "response.png"), DPI),
            plotting.save(plotting.bifurcation_figure(sweep, cols, poincare), os.path.join(out_dir, "bifurcation.png"),
                          DPI)]
