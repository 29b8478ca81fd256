"""Amplitude-frequency response and bifurcation diagrams of the paper's system (part of the main job).

  vibroimpact diagrams [--workers N | --scheduler ADDRESS] [--out DIR] [--gallery DIR] [--quick]

Hertz and Johnson (Y = 6e8 Pa) contact with the paper's data (R* = 0.475 m, steel, P = 40 kN =
10 m g), excitation frequency swept up and down as continuation sweeps (each point starts from the
previous point's final state, the frequency changed at phase 0), at the paper's amplitude
a = 0.1 mm and at a = 5 um, where the jump sits at the contact resonance. Writes, under --out
(default results/diagrams):
  <law>_<amplitude>_<up|down>/   each sweep's sweep.csv, poincare.csv, sweep.json and PNGs (vibroimpact sweep's files)
  frequency_response.png         maximum/minimum force, largest separation, contact fraction against f
  bifurcation.png                the Poincare indentation (once per period after the transient) against f
  summary.csv                    per sweep: where the mass first leaves the platform, the largest force and flight
--gallery DIR also writes smaller copies of the two figures there as sweep_<name>.png (the
documentation's: --gallery doc/gallery). --quick: coarse grids.
"""
import argparse
import pathlib
import sys
import time

from .. import diagrams, plotting
from ..failure import out_dir as make_out_dir
from ..files import save_figure
from ..fmu import fmu_path
from ..sweep import engine, spec
from .sweep import write_figures

OUT = pathlib.Path("results", "diagrams")
DPI, GALLERY_DPI = 100, 75


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact diagrams", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes of the local cluster (default: all cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS", help="a running Dask scheduler instead")
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR", help=f"output folder (default {OUT})")
    p.add_argument("--gallery", type=pathlib.Path, default=None, metavar="DIR",
                   help="also write smaller copies of the figures to DIR (the documentation's: doc/gallery)")
    p.add_argument("--quick", action="store_true", help="coarse grids and a coarser step")
    args = p.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        p.error("--workers must be at least 1")
    fmu = str(fmu_path())
    interface = spec.Interface(fmu)
    if not interface.variables["f"].tunable:
        print("diagrams: skipped: this FMU declares f fixed, and the continuation sweeps change it on a "
              "running instance (f must be tunable)", file=sys.stderr)
        return
    make_out_dir(args.out)
    gallery = args.gallery and make_out_dir(args.gallery, "--gallery")
    t0 = time.perf_counter()
    runs = run_sweeps(args, interface, fmu)
    wall = time.perf_counter() - t0
    fc = {law: diagrams.f_contact(fmu, interface, diagrams.PAPER + sets) for law, _, sets in diagrams.LAWS}
    figures = {"frequency_response.png": plotting.diagrams_response_figure(runs, fc, diagrams.panels(),
                                                                           diagrams.STOP_TIME, diagrams.TRANSIENT),
               "bifurcation.png": plotting.diagrams_bifurcation_figure(runs, fc, diagrams.panels())}
    for name, fig in figures.items():
        if gallery:
            save_figure(fig, gallery / f"sweep_{name}", GALLERY_DPI)
        plotting.save(fig, args.out / name, DPI)
    diagrams.write_summary(runs, args.out / "summary.csv")
    print(f"diagrams: {sum(len(c['f']) for c, _ in runs.values())} points in {wall:.0f} s -> "
          f"{', '.join(str(args.out / f) for f in figures)}, {args.out / 'summary.csv'}")


def run_sweeps(args, interface, fmu):
    """Every (amplitude, law, direction) sweep on Dask, each written to its folder: their files read back."""
    runs = {}
    with engine.connect(workers=args.workers, scheduler=args.scheduler) as client:
        for amp, a, grid, grid_quick in diagrams.AMPLITUDES:
            for law, _, law_sets in diagrams.LAWS:
                sets = diagrams.PAPER + law_sets + [f"a={a}"]
                for direction in diagrams.DIRECTIONS:
                    sw = diagrams.sweep_of(interface, sets, grid_quick if args.quick else grid, direction, args.quick)
                    out = args.out / f"{law}_{amp}_{direction}"
                    rows = engine.run(sw, interface, fmu, client=client, progress=False)
                    engine.write(out, sw, rows, argv=["vibroimpact", "diagrams"])
                    write_figures(out, sw)
                    runs[law, amp, direction] = engine.read(out)
                    print(f"diagrams: {out}: {len(rows)} points, "
                          f"{sum(r['status'] != 'ok' for _, r in rows)} failed", flush=True)
    return runs
