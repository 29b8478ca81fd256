"""Simulate the paper's scenarios through fmpy; write <out>/<scenario>.csv and .png, an overview
image (<out>/overview.png) and a table of figures (<out>/summary.csv); <out> is results/ by default.

    vibroimpact paper [--out DIR] [--gallery DIR] [scenario ...]   (default: every scenario of the table)

A run of some scenarios updates their rows of <out>/summary.csv and keeps the others; the overview
draws every scenario whose <out>/<scenario>.csv is there. --gallery DIR also writes smaller copies of
the images there (the documentation's are made with --gallery doc/gallery). A warning the FMU logs
in a scenario's run (an indentation beyond the model's range, for example) is printed to stderr once,
after the scenario's name, and kept in the column `warnings` of its row of summary.csv.

The scenarios are the one table in vibroimpact/reference/scenarios.py; the FMU is
vibroimpact.fmu_path(). Runs use rtol 1e-11 (not the FMU's default 1e-6): the bouncing scenarios
are chaotic, and the tighter tolerance keeps the drawn trajectory on the reference's for longer
(vibroimpact/reference/data/summary.json has each scenario's predictable horizon).
"""
import argparse
import pathlib

from .. import paper, plotting
from ..failure import out_dir
from ..files import save_figure
from ..fmu import Relay, fmu_path
from ..reference.scenarios import SCENARIOS

OUT = pathlib.Path("results")
DPI = 100           # the scenario figures; the overview 90
GALLERY_SCALE = 0.6  # the gallery copies' resolution against the figures'


def save(fig, out, filename, dpi, gallery):
    if gallery:
        save_figure(fig, gallery / filename, GALLERY_SCALE * dpi)
    plotting.save(fig, out / filename, dpi)


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact paper", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenarios", nargs="*", metavar="scenario", help=f"default: all ({', '.join(SCENARIOS)})")
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR", help=f"output folder (default {OUT})")
    p.add_argument("--gallery", type=pathlib.Path, default=None, metavar="DIR",
                   help="also write smaller copies of the images to DIR (the documentation's: doc/gallery)")
    a = p.parse_args(argv)
    unknown = [n for n in a.scenarios if n not in SCENARIOS]
    if unknown:
        p.error(f"unknown scenario {', '.join(unknown)}; the scenarios are {', '.join(SCENARIOS)}")
    names = a.scenarios or list(SCENARIOS)
    fmu_path()   # no FMU: say so before anything is written
    out = out_dir(a.out)
    gallery = a.gallery and out_dir(a.gallery, "--gallery")
    rows = paper.read_summary(out)
    relay = Relay("paper")
    for name in names:
        scenario = SCENARIOS[name]
        r = paper.simulate(scenario, warned=lambda texts: relay(name, texts))   # noqa: B023 (called at once)
        paper.write_run(out / f"{name}.csv", r)
        s = paper.summarize(name, r, relay.of(name))
        save(plotting.scenario_figure(scenario, r, s), out, f"{name}.png", DPI, gallery)
        rows[name] = paper.summary_row(s)
        paper.write_summary(out, rows)   # after each scenario: an interrupted run keeps what it finished
        print(f"{name}: {s['n_impacts']} impacts, max force {s['F_max_kN']:.1f} kN, mean force "
              f"{s['F_mean_kN']:.2f} kN, in contact {100 * s['contact_fraction']:.0f}% of the time, "
              f"W_plastic {s['W_plastic_J']:.4g} J"
              + (f", {len(relay.of(name))} FMU warning(s) (above; in summary.csv)" if relay.of(name) else "")
              + f" -> {out / name}.csv, {out / name}.png")
    runs = {n: (SCENARIOS[n], paper.read_run(out / f"{n}.csv")) for n in SCENARIOS if (out / f"{n}.csv").is_file()}
    save(plotting.overview_figure(runs), out, "overview.png", 90, gallery)
    print(f"overview -> {out / 'overview.png'}, figures -> {out / 'summary.csv'}")
