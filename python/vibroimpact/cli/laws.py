"""What each contact law and option changes in a scene and what it costs: the table and figure of
doc/choosing.md.

    vibroimpact laws [--out DIR] [--scenes NAME ...] [--repeat N] [--gallery DIR]
        ->  DIR/{laws.csv, laws.md, laws.png, laws_walls.png, corrugation.txt, roughness.txt}

--gallery DIR also writes smaller copies there of the figures whose scenes ran (the documentation's:
--gallery doc/gallery). Scenes: drop_0.1, drop_1, drop_3 (a steel sphere dropped on a steel plane), fig4b
(the paper's harmonic excitation), rolling (the paper's wheel over a corrugated rail near resonance),
vehicle_track (the vehicle-track example: needs its Track.fmu and Vehicle.fmu beside the FMU, as a
checkout's build/ has them), impact_damper (the sphere in a cavity 10 mm high shaken 1 mm at 50 Hz, no
gravity: the upper stop) and clearance (the sphere in a clearance of 0.5 mm under gravity on the same
platform); every variant of vibroimpact.laws_guide.VARIANTS in each. A CPU time "failed" is a run whose
integrator gave up (the command prints why). For vehicle_track a second table gives how far the
co-simulation at small steps is from the Model Exchange master, per variant; for impact_damper and
clearance a table of what each wall sees over the settled second half (the speed the sphere leaves a wall
with, against the impact damper's closed form; impacts per cycle and peak force on each wall; energy
dissipated per cycle) and laws_walls.png, the sphere between the walls over the last cycles. CPU times are
the smallest of --repeat runs (process time, this machine: compare them with each other, not with another
machine's). A warning the FMU logs in a run is printed to stderr once per scene and variant and listed in
laws.md. An unknown scene is refused before anything is written, and a run that fails or is interrupted
leaves the files of an earlier run as they were.
"""
import argparse
import pathlib

from .. import laws_guide, plotting
from ..failure import out_dir
from ..files import save_figure, write_text
from ..fmu import Relay, fmu_path

OUT = pathlib.Path("results", "laws")
DPI, GALLERY_DPI = 110, 70


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact laws", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR", help=f"output folder (default {OUT})")
    p.add_argument("--scenes", nargs="+", default=None, metavar="NAME", help="only these scenes (default: all)")
    p.add_argument("--repeat", type=int, default=3, metavar="N", help="runs per CPU time, the smallest counts (default 3)")
    p.add_argument("--gallery", type=pathlib.Path, default=None, metavar="DIR",
                   help="also write smaller copies of the figures to DIR (the documentation's: doc/gallery)")
    args = p.parse_args(argv)
    unknown = laws_guide.unknown_names(args.scenes or (), laws_guide.SCENES)
    if unknown:
        p.error(f"unknown scene {', '.join(unknown)}; the scenes are {', '.join(laws_guide.SCENES)}")
    if args.repeat < 1:
        p.error("--repeat is at least 1")
    fmu = fmu_path()   # no FMU: say so before anything is written
    out = out_dir(args.out)
    gallery = args.gallery and out_dir(args.gallery, "--gallery")
    relay = Relay("laws")
    rows = laws_guide.run(out, fmu, only_scenes=args.scenes, repeat=args.repeat, warned=relay)
    table = laws_guide.markdown(rows)
    agreement = laws_guide.agreement_markdown(rows)
    if agreement:
        table += ("\nvehicle_track: the Model Exchange master against the co-simulation, "
                  f"max |F_mean,CS - F_mean,ME| / W over {laws_guide.AGREEMENT_MEAN:g} s\n\n" + agreement)
    walls = laws_guide.walls_markdown(rows)
    if walls:
        table += ("\nimpact_damper and clearance: what each wall sees over the second half (settled); the closed form "
                  "of the impact damper for the variant's e_restitution\n\n" + walls)
    if relay.by_run:
        table += "\nThe FMU's warnings (also printed as they came):\n\n" + "".join(
            f"- {run}: {text}\n" for run, texts in relay.by_run.items() for text in texts)
    fig = laws_guide.figure(rows)
    walls_fig = laws_guide.walls_figure(rows)
    # every result made before the first is written; each file replaced only once complete
    laws_guide.write_csv(out / "laws.csv", rows)
    write_text(out / "laws.md", table)
    if gallery:   # the copies of the figures whose scenes ran
        if any(r["scene"] not in laws_guide.WALL_SCENES for r in rows):
            save_figure(fig, gallery / "laws.png", GALLERY_DPI)
        if walls_fig is not None:
            save_figure(walls_fig, gallery / "laws_walls.png", GALLERY_DPI)
    plotting.save(fig, out / "laws.png", DPI)
    if walls_fig is not None:
        plotting.save(walls_fig, out / "laws_walls.png", DPI)
    print(table)
