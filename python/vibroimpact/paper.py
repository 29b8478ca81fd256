"""Simulate the paper's scenarios through fmpy; write <out>/<scenario>.csv and .png, an overview
image (<out>/overview.png) and a table of figures (<out>/summary.csv); <out> is results/ by default.

    vibroimpact paper [--out DIR] [--gallery] [scenario ...]   (default: every scenario of the table)

A run of some scenarios updates their rows of <out>/summary.csv and keeps the others; the overview
draws every scenario whose <out>/<scenario>.csv is there.

The scenarios are the one table in vibroimpact/reference/scenarios.py; the FMU is
vibroimpact.fmu_path(). Runs use rtol 1e-11 (not the FMU's default 1e-6): the bouncing scenarios
are chaotic, and the tighter tolerance keeps the drawn trajectory on the reference's for longer
(vibroimpact/reference/data/summary.json has each scenario's predictable horizon).
"""
import argparse
import csv
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from .failure import out_dir  # noqa: E402
from .fmu import fmu_path, simulate as simulate_logged  # noqa: E402
from .reference.scenarios import SCENARIOS, STOP_TIME  # noqa: E402

OUT = pathlib.Path("results")
GALLERY = pathlib.Path("doc", "gallery")
INTERVAL = 1e-5  # s, output grid
RTOL = 1e-11
OUTPUTS = ["yC", "y", "delta", "F", "v", "contact", "mode", "n_impacts", "delta_c", "delta_f", "delta_p",
           "Rbar", "W_plastic"]
SUMMARY = ["scenario", "n_impacts", "F_min_kN", "F_max_kN", "F_mean_kN", "contact_fraction", "stick_fraction",
           "delta_max_um", "delta_p_um", "delta_f_um", "W_plastic_J", "y_p2p_mm"]


def simulate(scenario):
    return simulate_logged(f"the FMU refuses the scenario '{scenario.title}'", fmu_path(), start_values=scenario.full,
                           stop_time=STOP_TIME, output_interval=INTERVAL, relative_tolerance=RTOL, output=OUTPUTS)


def summarize(name, r):
    """The figures of one run (Python numbers: fmpy's result keeps its own type through max() and the like)."""
    return dict(scenario=name, n_impacts=int(r["n_impacts"][-1]), F_min_kN=float(r["F"].min()) / 1e3,
                F_max_kN=float(r["F"].max()) / 1e3,
                F_mean_kN=float(np.trapezoid(r["F"], r["time"])) / (r["time"][-1] - r["time"][0]) / 1e3,
                contact_fraction=float(np.mean(r["contact"])), stick_fraction=float(np.mean(r["mode"] == 4)),
                delta_max_um=float(r["delta"].max()) * 1e6,
                delta_p_um=float(r["delta_p"][-1]) * 1e6, delta_f_um=float(r["delta_f"][-1]) * 1e6,
                W_plastic_J=float(r["W_plastic"][-1]), y_p2p_mm=float(np.ptp(r["y"])) * 1e3)


def draw_positions(ax, r, lepp, lw=1.0):
    """Paper style: 1 thin, the platform yC(t); 2 bold, the mass y(t); LEPP (Fig. 6) adds the
    platform's unloaded surface yC - delta_p (the indentation is then the gap between it and y)."""
    ms = 1e3 * r["time"]
    ax.plot(ms, 1e3 * r["yC"], lw=0.5 * lw, color="k", label="1: platform $y_C(t)$")
    if lepp:
        ax.plot(ms, 1e3 * (r["yC"] - r["delta_p"]), lw=0.5 * lw, color="C2", label="2: $y_C - \\delta_p$")
    ax.plot(ms, 1e3 * r["y"], lw=1.3 * lw, color="C0", label=f"{3 if lepp else 2}: mass $y(t)$")
    ax.set_ylabel("position [mm]")


def save(fig, out, filename, dpi, gallery):
    fig.savefig(out / filename, dpi=dpi)
    if gallery:
        GALLERY.mkdir(parents=True, exist_ok=True)
        fig.savefig(GALLERY / filename, dpi=0.6 * dpi)
    plt.close(fig)


def plot(out, name, scenario, r, s, gallery):
    lepp = scenario.full.get("contact_model") == 3
    fig = plt.figure(figsize=(10, 7))
    grid = fig.add_gridspec(2, 2, height_ratios=[1.2, 1], width_ratios=[1.6, 1])
    ax = fig.add_subplot(grid[0, :])
    draw_positions(ax, r, lepp)
    ax.set_xlabel("time [ms]")
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"{scenario.title}\n{s['n_impacts']} impacts, max force {s['F_max_kN']:.0f} kN, "
                 f"W_plastic {s['W_plastic_J']:.3g} J", fontsize=10)
    ax = fig.add_subplot(grid[1, 0])
    ax.plot(1e3 * r["time"], 1e-3 * r["F"], lw=0.7, color="C3")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("contact force F [kN]")
    ax = fig.add_subplot(grid[1, 1])
    ax.plot(1e6 * r["delta"], 1e-3 * r["F"], lw=0.5, color="C3")
    ax.set_xlim(left=min(0.0, 1e6 * r["delta"][r["F"] > 0].min(initial=0.0)))
    ax.set_xlabel(r"indentation $\delta$ [$\mu$m]")
    ax.set_ylabel("F [kN]")
    fig.tight_layout()
    save(fig, out, f"{name}.png", 100, gallery)


def overview(out, runs, gallery):
    names = list(runs)
    cols = 3
    rows = -(-len(names) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(13, 2.6 * rows), squeeze=False)
    for ax, name in zip(axes.flat, names):
        scenario, r = runs[name]
        draw_positions(ax, r, scenario.full.get("contact_model") == 3, lw=0.7)
        ax.set_title(scenario.title, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.yaxis.label.set_size(7)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    fig.suptitle("VibroImpact FMU: the paper's scenarios (thin: platform, bold: mass; time in ms)", fontsize=10)
    fig.tight_layout()
    save(fig, out, "overview.png", 90, gallery)


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact paper", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenarios", nargs="*", metavar="scenario", help=f"default: all ({', '.join(SCENARIOS)})")
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR", help=f"output folder (default {OUT})")
    p.add_argument("--gallery", action="store_true", help=f"also write smaller copies of the images to {GALLERY}/")
    a = p.parse_args(argv)
    unknown = [n for n in a.scenarios if n not in SCENARIOS]
    if unknown:
        p.error(f"unknown scenario {', '.join(unknown)}; the scenarios are {', '.join(SCENARIOS)}")
    names, gallery = a.scenarios or list(SCENARIOS), a.gallery
    fmu_path()   # no FMU: say so before anything is written
    out = out_dir(a.out)
    rows = read_summary(out)
    for name in names:
        scenario = SCENARIOS[name]
        r = simulate(scenario)
        np.savetxt(out / f"{name}.csv", np.column_stack([r[c] for c in r.dtype.names]), delimiter=",",
                   header=",".join(r.dtype.names), comments="", fmt="%.10g")
        s = summarize(name, r)
        plot(out, name, scenario, r, s, gallery)
        rows[name] = {k: f"{s[k]:.6g}" if isinstance(s[k], float) else str(s[k]) for k in SUMMARY}
        write_summary(out, rows)   # after each scenario: an interrupted run keeps what it finished
        print(f"{name}: {s['n_impacts']} impacts, max force {s['F_max_kN']:.1f} kN, mean force "
              f"{s['F_mean_kN']:.2f} kN, in contact {100 * s['contact_fraction']:.0f}% of the time, "
              f"W_plastic {s['W_plastic_J']:.4g} J -> {out / name}.csv, {out / name}.png")
    overview(out, {n: (SCENARIOS[n], read_run(out / f"{n}.csv")) for n in SCENARIOS if (out / f"{n}.csv").is_file()},
             gallery)
    print(f"overview -> {out / 'overview.png'}, figures -> {out / 'summary.csv'}")


def read_summary(out):
    """The rows of <out>/summary.csv by scenario (text as written), those of known scenarios only."""
    path = out / "summary.csv"
    if not path.is_file():
        return {}
    with open(path, newline="") as fh:
        found = list(csv.DictReader(fh))
    return {r["scenario"]: r for r in found if r.get("scenario") in SCENARIOS and set(SUMMARY) <= set(r)}


def write_summary(out, rows):
    """<out>/summary.csv: one row per scenario in `rows`, in the scenario table's order."""
    tmp = out / "summary.csv.tmp"
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(SUMMARY)
        for name in (n for n in SCENARIOS if n in rows):
            w.writerow([rows[name][k] for k in SUMMARY])
    tmp.replace(out / "summary.csv")


def read_run(path):
    """A scenario's CSV file back as {output name: column}, the columns simulate() returned."""
    with open(path) as fh:
        names = fh.readline().strip().split(",")
    return dict(zip(names, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2).T))
