"""Rolling over a corrugated rail (paper Fig. 1b; Fig. 5-like): the wheel of the paper (R1 = 0.475 m,
Hertz, P = 40 kN = 10 m g) rolls over a sinusoidal corrugation at three speeds, so that the passing
frequency V/lambda lies below, near and above the contact resonance.

    vibroimpact rolling [--out DIR] [--gallery DIR]
        ->  DIR/{corrugation.txt, rolling.png, rolling.csv, constraint_harmonics.csv}

--gallery DIR also writes a smaller copy of the figure there (the documentation's: --gallery doc/gallery).
A warning the FMU logs in a case's run is printed to stderr once, after the case's name, and kept in
rolling.csv's column warnings.
The FMU is vibroimpact.fmu_path(); the constraint drawn beside it comes from the independent
reference (vibroimpact.reference.profile).
"""
import argparse
import pathlib

from .. import plotting, rolling
from ..failure import out_dir
from ..files import save_figure
from ..fmu import Relay, fmu_path

OUT = pathlib.Path("results", "rolling")
DPI, GALLERY_DPI = 110, 60


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact rolling", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR", help=f"output folder (default {OUT})")
    p.add_argument("--gallery", type=pathlib.Path, default=None, metavar="DIR",
                   help="also write a smaller copy of the figure to DIR/rolling.png (the documentation's: doc/gallery)")
    args = p.parse_args(argv)
    fmu = fmu_path()
    out = out_dir(args.out)
    gallery = args.gallery and out_dir(args.gallery, "--gallery")
    x, h = rolling.corrugation(out / "corrugation.txt")
    relay = Relay("rolling")
    runs = rolling.run(out / "corrugation.txt", fmu, warned=relay)
    fig = plotting.rolling_figure((*rolling.constraint(x, h), rolling.R1), runs, rolling.PASSING)
    if gallery:
        save_figure(fig, gallery / "rolling.png", GALLERY_DPI)
    plotting.save(fig, out / "rolling.png", DPI)
    table = rolling.rows(runs, relay.by_run)
    rolling.write_rows(out / "rolling.csv", table)
    amp = rolling.harmonics(x, h)
    rolling.write_harmonics(out / "constraint_harmonics.csv", amp)
    print("harmonics of yb [um]: " + ", ".join(f"{k}: {a * 1e6:.3g}" for k, a in enumerate(amp, start=1)))
    for row in table:   # the warnings were printed as they came
        print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()
                        if k != "warnings"))
