"""The vehicle-track system without coupling error, against the example's monolithic reference: the
three FMUs imported as Model Exchange and integrated together by one solver. The master itself is
vibroimpact.vehicle_track.me_master (the package's `vibroimpact laws` runs it too); its names are
importable from here, with compare(), the errors of a run against the reference.

    python3 me_master.py [--stop-time T] [--rtol R ...] [--method DOP853] [--profile FILE] [--no-rail-velocity]
"""
import argparse
import pathlib
import tempfile
import time

import numpy as np
from vibroimpact.vehicle_track.me_master import (CONNECTIONS, FMUS, MAX_EVENT_PASSES, QUADRATURE_NOMINAL,  # noqa: F401
                                                 QUADRATURES, RECORDED, SPAN, Coupled, MeFmu, feedthrough,
                                                 past_crossing, plan, run)

import parameters
import reference


def compare(r, sol, system, mean_step=1e-5):
    """Errors of a run against the reference solution (W: the static wheel load): the force on the
    grid, the mean force over mean_step from the impulse, the impulse and the dissipated work over
    the run, the positions of the wheel and the rail."""
    t, W = r["t"], system.W
    every = max(int(round(mean_step / (t[1] - t[0]))), 1)
    tm = t[::every]
    J_ref = sol.state(t[-1])[reference.J, 0] - sol.state(t[0])[reference.J, 0]
    D_ref = sol.state(t[-1])[reference.D, 0]
    x = sol.state(t)
    return {"force_error": float(np.max(np.abs(r["contact.F"] - sol.force(t))) / W),
            "mean_force_error": float(np.max(np.abs(np.diff(r["J"][::every]) / np.diff(tm) - sol.mean_force(tm))) / W),
            "peak_error": float(r["contact.F"].max() / sol.force(t).max() - 1.0),
            "impulse_error": float((r["J"][-1] - r["J"][0] - J_ref) / J_ref),
            "dissipation_error": float((r["D"][-1] - D_ref) / D_ref),
            "y_error_m": float(np.max(np.abs(r["contact.y"] - x[reference.YW]))),
            "z_rail_error_m": float(np.max(np.abs(r["track.z_rail"] - x[reference.ZR])))}


def main():
    import roughness
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stop-time", type=float, default=parameters.STOP_TIME)
    ap.add_argument("--rtol", type=float, nargs="+", default=[1e-8], help="the solver's relative tolerances")
    ap.add_argument("--method", default="DOP853", help="solve_ivp's method (DOP853, RK45, Radau, BDF, LSODA)")
    ap.add_argument("--profile", help="profile file (x, h); default: the example's roughness")
    ap.add_argument("--no-rail-velocity", action="store_true",
                    help="leave v_rail -> vC_in out (velocity_input = false: the contact FMU estimates the "
                         "rail's rate)")
    a = ap.parse_args()
    connections = [c for c in CONNECTIONS if not (a.no_rail_velocity and c[3] == "vC_in")]
    with tempfile.TemporaryDirectory(prefix="vt_me_") as tmp:
        profile = a.profile
        if not profile:
            profile = pathlib.Path(tmp) / "profile.txt"
            roughness.write(profile, *roughness.profile(**parameters.ROUGHNESS))
        compare_runs(profile, a.stop_time, a.rtol, a.method, connections)


def compare_runs(profile, stop_time, rtols, method, connections=CONNECTIONS):
    """The reference and a Model Exchange run per tolerance, printed."""
    system = reference.default_system(profile, stop_time)
    cpu0 = time.process_time()
    sol = reference.simulate(system, stop_time, rtol=1e-10)
    print(f"reference: {time.process_time() - cpu0:.1f} s CPU, contact changes at "
          f"{', '.join(f'{t:.9f}' for t, _ in sol.events) or 'none'} s")
    for rtol in rtols:
        r = run(stop_time, profile, rtol=rtol, method=method, connections=connections)
        m = compare(r, sol, system)
        print(f"Model Exchange, {method}, rtol {rtol:g}: {r['cpu_s']:.1f} s CPU, {r['evaluations']} evaluations, "
              f"{r['time_events']} time events, state events at "
              f"{', '.join(f'{t:.9f}' for t in r['state_events']) or 'none'} s; against the reference: force "
              f"{m['force_error']:.1e} W, mean force {m['mean_force_error']:.1e} W, impulse {m['impulse_error']:+.1e}, "
              f"dissipated work {m['dissipation_error']:+.1e}; wheel {m['y_error_m']:.1e} m, "
              f"rail {m['z_rail_error_m']:.1e} m")


if __name__ == "__main__":
    main()
