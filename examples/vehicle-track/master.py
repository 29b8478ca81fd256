"""The fmpy co-simulation master of the vehicle-track example, from the command line. The master itself
is vibroimpact.vehicle_track.master (the package's `vibroimpact laws` runs it too); its names are
importable from here.

    python3 master.py [--step H] [--stop-time T] [--scheme gauss-seidel|jacobi] [--order a,b,c]
                      [--force F|F_mean] [--rail-motion hold|ramp|derivative] [--profile FILE] [--excitation A F]
"""
import argparse
import time

from vibroimpact.vehicle_track.master import (CONNECTIONS, CONTACT_IN, CONTACT_OUT, RAIL_MOTIONS,  # noqa: F401
                                              TRACK_OUT, VEHICLE_OUT, Slave, build_dir, contact_start_values, run)

import parameters


def main():
    ap = argparse.ArgumentParser(description="fmpy master for the vehicle-track example")
    ap.add_argument("--step", type=float, default=1e-5)
    ap.add_argument("--stop-time", type=float, default=parameters.STOP_TIME)
    ap.add_argument("--scheme", choices=["gauss-seidel", "jacobi"], default="gauss-seidel")
    ap.add_argument("--order", default="vehicle,contact,track")
    ap.add_argument("--force", choices=["F", "F_mean"], default="F_mean")
    ap.add_argument("--rail-motion", choices=RAIL_MOTIONS, default="hold",
                    help="the rail within a step: held, on a line at v_rail through vC_in (ramp, velocity_input) "
                         "or through the derivative of yC_in (derivative)")
    ap.add_argument("--profile")
    ap.add_argument("--excitation", type=float, nargs=2, metavar=("A", "F"))
    a = ap.parse_args()
    t0 = time.time()
    r = run(a.step, a.stop_time, a.scheme, a.order.split(","), a.force, a.rail_motion, a.profile, a.excitation)
    F = r["contact.F"]
    print(f"{time.time() - t0:.1f} s: F {F.min():.0f} .. {F.max():.0f} N, energy created by the coupling "
          f"{r['E_coupling'][-1]:.3e} J")


if __name__ == "__main__":
    main()
