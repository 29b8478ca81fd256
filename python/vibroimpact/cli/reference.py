"""Recompute the reference traces and event tables with the independent reference model, and each
scenario's predictable horizon (vibroimpact.reference.generate).

    vibroimpact reference [scenario ...] [--out DIR]     (default: every scenario, into results/reference)

The committed traces the tests compare with are refreshed with
--out python/vibroimpact/reference/data (in a checkout). Writes <name>.trace.csv.gz and
<name>.events.csv per scenario and updates summary.json.
"""
import argparse
import pathlib

from ..failure import out_dir
from ..reference.generate import DATA, update
from ..reference.scenarios import SCENARIOS

OUT = pathlib.Path("results", "reference")


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact reference", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenarios", nargs="*", metavar="scenario", help=f"default: all ({', '.join(SCENARIOS)})")
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR",
                   help=f"output folder (default {OUT}; the committed traces are in {DATA})")
    a = p.parse_args(argv)
    unknown = [n for n in a.scenarios if n not in SCENARIOS]
    if unknown:
        p.error(f"unknown scenario {', '.join(unknown)}; the scenarios are {', '.join(SCENARIOS)}")
    update(a.scenarios or list(SCENARIOS), out_dir(a.out))
