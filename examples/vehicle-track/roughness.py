"""The example's rail roughness profile, from the command line: vibroimpact.vehicle_track.roughness
(a seeded random profile with the one-third octave band spectrum of the ISO 3095:2013 rail roughness
limit, raised by a chosen number of decibels); its names are importable from here.

    python3 roughness.py out.txt [--level-db 15] [--seed 1] [--length 6] [--dx 1e-3]
"""
import argparse

from vibroimpact.vehicle_track.roughness import (BAND_HALF_WIDTH, ISO3095_LIMIT_DB, band_levels,  # noqa: F401
                                                 components, profile, taper, write)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--level-db", type=float, default=15.0, help="dB above the ISO 3095 limit")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--length", type=float, default=6.0, help="m")
    ap.add_argument("--dx", type=float, default=1e-3, help="m")
    a = ap.parse_args()
    x, h = profile(a.length, a.dx, a.level_db, a.seed)
    write(a.out, x, h)


if __name__ == "__main__":
    main()
