"""Amplitude-frequency response and bifurcation diagrams of the paper's system (part of the main job).

  vibroimpact diagrams [--workers N | --scheduler ADDRESS] [--out DIR] [--gallery] [--quick]

Hertz and Johnson (Y = 6e8 Pa) contact with the paper's data (R* = 0.475 m, steel, P = 40 kN =
10 m g), excitation frequency swept up and down as continuation sweeps (each point starts from the
previous point's final state, the frequency changed at phase 0), at the paper's amplitude
a = 0.1 mm and at a = 5 um, where the jump sits at the contact resonance. Writes, under --out
(default results/diagrams):
  <law>_<amplitude>_<up|down>/   each sweep's sweep.csv, poincare.csv, sweep.json and PNGs (vibroimpact sweep's files)
  frequency_response.png         maximum/minimum force, largest separation, contact fraction against f
  bifurcation.png                the Poincare indentation (once per period after the transient) against f
  summary.csv                    per sweep: where the mass first leaves the platform, the largest force and flight
--gallery also writes smaller copies to doc/gallery/ (of the current folder). --quick: coarse grids.
"""
import argparse
import csv
import pathlib
import sys
import time

import numpy as np

from .failure import out_dir as make_out_dir
from .fmu import fmu_path
from .sweep import engine, plots, spec

OUT = pathlib.Path("results", "diagrams")
GALLERY = pathlib.Path("doc", "gallery")

PAPER = ["R1=0.475", "R2=0", "E1=2.1e11", "E2=2.1e11", "nu1=0.3", "nu2=0.3", "P=40000", "m=407.747", "g=9.81",
         "init=static"]
LAWS = [("hertz", "Hertz", ["contact_model=hertz"]),
        ("johnson", "Johnson, Y = 6e8 Pa", ["contact_model=johnson", "Y=6e8"])]
# amplitude label, a [m], frequency grid START:STOP:N (full, quick)
AMPLITUDES = [("a100um", 1e-4, "f=100:600:51", "f=100:600:26"),
              ("a5um", 5e-6, "f=200:330:66", "f=200:330:27")]
STOP_TIME, TRANSIENT, STEP = 0.1, 0.05, 1e-5  # per point [s]
DIRECTIONS = [("up", "C0", "^"), ("down", "C1", "v")]


def f_contact(fmu, interface, sets):
    """The FMU's calculated linearised contact resonance for these start values."""
    from fmpy import simulate_fmu
    values = {n: v for n, v in (spec.parse_set(interface, s) for s in sets)}
    r = simulate_fmu(fmu, start_values=values, stop_time=1e-4, output_interval=1e-4, output=["f_contact"])
    return float(r["f_contact"][0])


def sweep_of(interface, sets, grid, direction, quick):
    fixed = dict(spec.parse_set(interface, s) for s in sets)
    return spec.Sweep(fixed=fixed, grids=[spec.parse_grid(interface, grid)], stop_time=STOP_TIME,
                      step=STEP * (4 if quick else 1), transient=TRANSIENT, direction=direction,
                      title=" ".join(s for s in sets if s not in PAPER))


def first_loss(cols, direction):
    """The first frequency, in the sweep's own order, at which the mass leaves the platform."""
    f = cols["f"][cols["contact_fraction"] < 1]
    return np.nan if not len(f) else (f.min() if direction == "up" else f.max())


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact diagrams", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes of the local cluster (default: all cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS", help="a running Dask scheduler instead")
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR", help=f"output folder (default {OUT})")
    p.add_argument("--gallery", action="store_true", help=f"also write smaller copies of the figures to {GALLERY}/")
    p.add_argument("--quick", action="store_true", help="coarse grids and a coarser step")
    args = p.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        p.error("--workers must be at least 1")
    fmu = str(fmu_path())
    out_dir = args.out
    interface = spec.Interface(fmu)
    if not interface.variables["f"].tunable:
        print("diagrams: skipped: this FMU declares f fixed, and the continuation sweeps change it on a "
              "running instance (f must be tunable)", file=sys.stderr)
        return
    make_out_dir(out_dir)
    runs, t0 = {}, time.perf_counter()
    with engine.connect(workers=args.workers, scheduler=args.scheduler) as client:
        for amp, a, grid, grid_quick in AMPLITUDES:
            for law, _, law_sets in LAWS:
                sets = PAPER + law_sets + [f"a={a}"]
                for direction, _, _ in DIRECTIONS:
                    sw = sweep_of(interface, sets, grid_quick if args.quick else grid, direction, args.quick)
                    out = out_dir / f"{law}_{amp}_{direction}"
                    rows = engine.run(sw, interface, fmu, client=client, progress=False)
                    engine.write(out, sw, rows, argv=["vibroimpact", "diagrams"])
                    plots.sweep_figures(out, sw)
                    runs[law, amp, direction] = engine.read(out)
                    print(f"diagrams: {out}: {len(rows)} points, "
                          f"{sum(r['status'] != 'ok' for _, r in rows)} failed", flush=True)
    wall = time.perf_counter() - t0
    fc = {law: f_contact(fmu, interface, PAPER + sets) for law, _, sets in LAWS}
    figures = [save(draw_response(runs, fc), out_dir, "frequency_response.png", args.gallery),
               save(draw_bifurcation(runs, fc), out_dir, "bifurcation.png", args.gallery)]
    write_summary(runs, out_dir)
    print(f"diagrams: {sum(len(c['f']) for c, _ in runs.values())} points in {wall:.0f} s -> "
          f"{', '.join(str(f) for f in figures)}, {out_dir / 'summary.csv'}")


def draw_response(runs, fc):
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(3, 2 * len(AMPLITUDES), figsize=(6 * len(AMPLITUDES) * 2 * 0.75, 8.5), sharex="col")
    for j, ((amp, a, _, _), (law, title, _)) in enumerate((x, y) for x in AMPLITUDES for y in LAWS):
        col = axes[:, j]
        for direction, color, marker in DIRECTIONS:
            cols, _ = runs[law, amp, direction]
            plots.draw_response(col, cols, "f", label=f"{direction}-sweep", color=color, marker=marker, ms=3, lw=0.8)
        for ax in col:
            ax.axvline(fc[law], color="k", lw=0.6, ls=":")
        col[0].set_title(f"{title}, a = {a * 1e6:g} $\\mu$m\n(dotted: f_contact = {fc[law]:.1f} Hz)", fontsize=9)
        col[-1].set_xlabel("excitation frequency f [Hz]")
        if j:
            for ax in col:
                ax.set_ylabel("")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Amplitude-frequency response: continuation up and down in f "
                 f"({STOP_TIME:g} s per point, statistics after {TRANSIENT:g} s)", fontsize=10)
    fig.tight_layout()
    return fig


def draw_bifurcation(runs, fc):
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(AMPLITUDES), len(LAWS), figsize=(12, 4.2 * len(AMPLITUDES)), squeeze=False)
    for i, (amp, a, _, _) in enumerate(AMPLITUDES):
        for j, (law, title, _) in enumerate(LAWS):
            ax = axes[i, j]
            for direction, color, marker in DIRECTIONS:
                _, pc = runs[law, amp, direction]
                plots.draw_bifurcation(ax, pc, "f", label=f"{direction}-sweep", color=color, s=3 if direction == "up" else 2,
                                       marker=marker, alpha=0.7)
            ax.axvline(fc[law], color="k", lw=0.6, ls=":")
            ax.set_title(f"{title}, a = {a * 1e6:g} $\\mu$m", fontsize=9)
            ax.set_xlabel("excitation frequency f [Hz]")
            ax.legend(fontsize=7, markerscale=3)
    fig.suptitle("Bifurcation diagrams: indentation once per excitation period (phase 0) after the transient",
                 fontsize=10)
    fig.tight_layout()
    return fig


def save(fig, out_dir, name, gallery):
    import matplotlib.pyplot as plt
    fig.savefig(out_dir / name, dpi=100)
    if gallery:
        GALLERY.mkdir(parents=True, exist_ok=True)
        fig.savefig(GALLERY / f"sweep_{name}", dpi=75)
    plt.close(fig)
    return out_dir / name


def write_summary(runs, out_dir):
    with open(out_dir / "summary.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["law", "amplitude", "direction", "points", "failed", "f_contact_lost_Hz",
                    "F_max_kN", "f_at_F_max_Hz", "sep_max_mm"])
        for (law, amp, direction), (cols, _) in runs.items():
            k = int(np.nanargmax(cols["F_max"]))
            w.writerow([law, amp, direction, len(cols["f"]), sum(s != "ok" for s in cols["status"]),
                        first_loss(cols, direction),
                        f"{cols['F_max'][k] / 1e3:.1f}", cols["f"][k], f"{np.nanmax(cols['sep_max']) * 1e3:.3f}"])
