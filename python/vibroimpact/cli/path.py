"""vibroimpact path: print the path of the FMU the commands use."""
import argparse
import sys

from ..fmu import fmu3_path, fmu_path


def main(argv=None):
    ap = argparse.ArgumentParser(prog="vibroimpact path",
                                 description="print the path of the FMU the commands use (vibroimpact.fmu_path())")
    ap.add_argument("--fmi3", action="store_true", help="the FMI 3.0 FMU beside it (vibroimpact.fmi3.fmu3_path())")
    try:
        print(fmu3_path() if ap.parse_args(argv).fmi3 else fmu_path())
    except FileNotFoundError as e:
        print(f"vibroimpact: {e}", file=sys.stderr)
        return 1
    return 0
