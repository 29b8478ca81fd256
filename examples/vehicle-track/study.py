"""The vehicle-track example's study: co-simulation and Model Exchange against the monolithic reference.

    python3 study.py [--build DIR] [--out results] [--quick] [--gallery]

Writes into --out (default examples/vehicle-track/results, not committed):
  profile.txt       the rail roughness (roughness.py: ISO 3095 limit + 15 dB, seeded)
  summary.csv       one row per coupling and communication step: errors against the reference
  errors.png        force error, mean-force error and energy created by the coupling against the step
  traces.png        contact force over a stretch of rail: reference and co-simulations
  libcosim.csv      libcosim against the fmpy master with the same (Jacobi) scheme
  model_exchange.csv  the three FMUs as Model Exchange in one solver (me_master.py), one row per
                    solver tolerance
  summary.md        the tables of examples/vehicle-track/README.md
--gallery also writes smaller copies of the two figures to examples/vehicle-track/doc/.

Couplings compared (fmpy master, master.py):
  GS hold   Gauss-Seidel vehicle -> contact -> track, the rail position held over the step
  GS ramp   the same, the contact FMU extrapolating the rail with its velocity (v_rail -> vC_in,
            velocity_input = true; the derivative of yC_in gives the same numbers)
  GS track first   vehicle -> track -> contact, the contact FMU interpolating the rail between the
            track's positions at both ends of the step (their slope in vC_in); the track gets the
            mean force of the step before
  Jacobi    every FMU with the outputs of the last communication point (libcosim's scheme), the
            rail held
  Jacobi ramp  the same with the rail extrapolated with its velocity (vC_in): libcosim with
            OspSystemStructure.xml as it is
each handing the track the end-of-step force F or the step's mean force F_mean; and on the FMI 3.0
FMUs (master3.py), Gauss-Seidel contact -> track -> vehicle with the rail extrapolated (der(yC_in))
and F_mean, without and with early return (the contact FMU stops at each contact loss and onset,
the others step to that instant). Against them: the three FMUs imported as Model Exchange and
integrated together by one solver (me_master.py: solve_ivp, DOP853, no communication step; its
metrics on a 1e-5 s output grid).
Metrics (W: static wheel load, 66.2 kN):
  force error        max over the communication points of |F - F_ref| / W
  mean-force error   max over the steps of |F_mean - (impulse of F_ref over the step)/step| / W
  impulse error      (impulse handed to the track - reference impulse on the wheel) / reference, whole run
  energy created     energy the coupling put in at the two ports over the run [J] (master.py), and
                     that over the energy the dampers dissipated in the reference run
  dissipation error  (work dissipated in the dampers over the run - reference) / reference
  cpu_s              CPU time of the run (FMUs included: they run in this process)
"""
import argparse
import csv
import pathlib
import time

import numpy as np

import master
import master3
import me_master
import parameters
import reference
import roughness

HERE = pathlib.Path(__file__).resolve().parent
STEPS = [1e-6, 2e-6, 5e-6, 1e-5, 2e-5, 5e-5, 1e-4]
COUPLINGS = [  # label, scheme, order, rail motion, force handed to the track
    ("GS hold, F", "gauss-seidel", ("vehicle", "contact", "track"), "hold", "F"),
    ("GS hold, F_mean", "gauss-seidel", ("vehicle", "contact", "track"), "hold", "F_mean"),
    ("GS ramp, F", "gauss-seidel", ("vehicle", "contact", "track"), "ramp", "F"),
    ("GS ramp, F_mean", "gauss-seidel", ("vehicle", "contact", "track"), "ramp", "F_mean"),
    ("GS track first, F_mean", "gauss-seidel", ("vehicle", "track", "contact"), "ramp", "F_mean"),
    ("Jacobi, F", "jacobi", None, "hold", "F"),
    ("Jacobi, F_mean", "jacobi", None, "hold", "F_mean"),
    ("Jacobi ramp, F", "jacobi", None, "ramp", "F"),
    ("Jacobi ramp, F_mean", "jacobi", None, "ramp", "F_mean"),
    ("FMI 3.0 contact first, F_mean", "fmi3", None, "ramp", "F_mean"),
    ("FMI 3.0 early return, F_mean", "fmi3 early return", None, "ramp", "F_mean"),
]
DIVERGED = 1.0  # a force error above the static wheel load: the coupling is unstable


def metrics(r, sol, system):
    """Errors of a co-simulation record against the reference solution."""
    t, W = r["t"], system.W
    F_ref = sol.force(t)
    Fm_ref = sol.mean_force(t)
    J_ref = sol.state(t[-1])[reference.J, 0] - sol.state(t[0])[reference.J, 0]
    D_ref = sol.state(t[-1])[reference.D, 0]
    h = t[1] - t[0]
    handed = r["F_to_track"][1:]
    return {
        "force_error": float(np.max(np.abs(r["contact.F"] - F_ref)) / W),
        "mean_force_error": float(np.max(np.abs(r["contact.F_mean"][1:] - Fm_ref)) / W),
        "peak_error": float(r["contact.F"].max() / F_ref.max() - 1.0),
        "impulse_error": float((np.sum(handed) * h - J_ref) / J_ref),
        "energy_created_J": float(r["E_coupling"][-1]),
        "energy_created_rel": float(r["E_coupling"][-1] / D_ref),
        "dissipation_error": float((r["track.W_dissipated"][-1] + r["vehicle.W_dissipated"][-1] - D_ref) / D_ref),
    }


ME_RTOLS = [1e-6, 1e-8, 1e-10]


def me_sweep(system, sol, rtols, stop_time, profile, excitation, build):
    rows, keep = [], {}
    for rtol in rtols:
        r = me_master.run(stop_time, profile, excitation, rtol=rtol, build=build)
        row = {"coupling": "Model Exchange, one solver", "rtol": rtol, "status": "ok", "cpu_s": round(r["cpu_s"], 2),
               "evaluations": r["evaluations"], "state_events": len(r["state_events"]),
               "time_events": r["time_events"], "energy_created_J": 0.0, "energy_created_rel": 0.0,
               **me_master.compare(r, sol, system)}
        rows.append(row)
        keep[rtol] = r
        print(" ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()))
    return rows, keep


def run_reference(profile, excitation, stop_time):
    system = reference.default_system(profile, stop_time, excitation)
    t0 = time.process_time()
    sol = reference.simulate(system, stop_time, rtol=1e-10)
    system.cpu_s = time.process_time() - t0
    print(f"reference: {system.cpu_s:.1f} s CPU, {len(sol.events)} contact changes, "
          f"energy balance {np.abs(sol.energy_residual(np.linspace(0, stop_time, 2001))).max():.1e} J")
    return system, sol


def sweep(system, sol, steps, couplings, stop_time, profile, excitation, build):
    rows, keep = [], {}
    for label, scheme, order, rail, force in couplings:
        for h in steps:
            t0, cpu0 = time.time(), time.process_time()
            try:
                if scheme.startswith("fmi3"):
                    r = master3.run(h, stop_time, force, rail, scheme == "fmi3 early return", profile, excitation,
                                    build)
                else:
                    r = master.run(h, stop_time, scheme, order or ("vehicle", "contact", "track"), force, rail,
                                   profile, excitation, build)
                m = metrics(r, sol, system)
                status = "ok" if np.isfinite(m["force_error"]) and m["force_error"] < DIVERGED else "diverged"
            except Exception as e:  # an unstable coupling can drive an FMU into an error
                m, status = {}, f"failed: {str(e).splitlines()[0][:80]}"
                r = None
            row = {"coupling": label, "step": h, "status": status, "wall_s": round(time.time() - t0, 2),
                   "cpu_s": round(time.process_time() - cpu0, 2), **m}
            if r is not None and "events" in r:
                row["early_returns"] = len(r["events"])
            rows.append(row)
            print(" ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()))
            if r is not None and h in (1e-5, 1e-4):
                keep[(label, h)] = r
    return rows, keep


def compare_libcosim(steps, stop_time, profile, excitation, build):
    import cosim
    rows = []
    for h in steps:
        for force in ("F", "F_mean"):
            rc = cosim.run(h, stop_time, force, profile, excitation, build)
            rm = master.run(h, stop_time, "jacobi", ("vehicle", "contact", "track"), force, "ramp", profile,
                            excitation, build)
            d = {k: float(np.nanmax(np.abs(rc[k][1:] - rm[k][1:]))) for k in rc if k != "t"}
            rows.append({"step": h, "force": force, "max_abs_diff_F_N": d["contact.F"],
                         "max_abs_diff_y_m": d["contact.y"], "max_abs_diff_z_rail_m": d["track.z_rail"],
                         "max_abs_diff_F_wheel_N": d["vehicle.F_wheel"]})
            print("libcosim vs fmpy (Jacobi)", rows[-1])
    return rows


def write_csv(path, rows):
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


COMPARED = [("GS ramp, F_mean", 1e-6), ("GS ramp, F_mean", 1e-5), ("FMI 3.0 early return, F_mean", 1e-6),
            ("FMI 3.0 early return, F_mean", 1e-5)]  # beside Model Exchange in its table


def markdown(rows, lc, path, me_rows=(), reference_cpu_s=None):
    """The tables of the README (examples/vehicle-track/README.md), from the rows."""
    steps = sorted({r["step"] for r in rows})
    labels = list(dict.fromkeys(r["coupling"] for r in rows))
    cell = {(r["coupling"], r["step"]): r for r in rows}

    def table(key, fmt, title):
        out = [f"**{title}**", "", "| coupling | " + " | ".join(f"{h:g} s" for h in steps) + " |",
               "|---|" + "---|" * len(steps)]
        for lab in labels:
            vals = []
            for h in steps:
                r = cell.get((lab, h), {})
                v = r.get(key)
                text = "failed" if v is None else fmt(v)
                vals.append(text + (" (unstable)" if r.get("status") == "diverged" else ""))
            out.append(f"| {lab} | " + " | ".join(vals) + " |")
        return "\n".join(out) + "\n"

    parts = [table("force_error", lambda v: f"{v:.2g}", "Force error, max |F - F_ref| / W"),
             table("mean_force_error", lambda v: f"{v:.2g}", "Mean-force error, max |F_mean - F_mean,ref| / W"),
             table("impulse_error", lambda v: f"{v:+.1e}", "Impulse error: impulse handed to the track over the run, relative"),
             table("energy_created_rel", lambda v: f"{v:+.1e}",
                   "Energy created by the coupling over the run / energy dissipated in the reference"),
             table("cpu_s", lambda v: f"{v:.1f}", "CPU time of the run [s]")]
    if me_rows:
        head = ("**Model Exchange: the three FMUs in one solver, against the co-simulation** (Model Exchange: "
                "force on a 1e-5 s grid, mean force over its intervals)\n\n"
                "| run | force error | mean-force error | impulse error | dissipated-energy error | "
                "energy created / dissipated | CPU [s] |\n|---|---|---|---|---|---|---|\n")
        lines = []
        if reference_cpu_s is not None:
            lines.append(f"| monolithic reference (DOP853, rtol 1e-10) | | | | | | {reference_cpu_s:.1f} |")
        for r in me_rows:
            lines.append(f"| Model Exchange, rtol {r['rtol']:g} ({r['evaluations']} evaluations, {r['time_events']} "
                         f"time events, {r['state_events']} state events) | {r['force_error']:.2g} | "
                         f"{r['mean_force_error']:.2g} | {r['impulse_error']:+.1e} | {r['dissipation_error']:+.1e} | "
                         f"none | {r['cpu_s']:.1f} |")
        for lab, h in COMPARED:
            r = cell.get((lab, h))
            if r is None or "force_error" not in r:
                continue
            lines.append(f"| {lab}, {h:g} s | {r['force_error']:.2g} | {r['mean_force_error']:.2g} | "
                         f"{r['impulse_error']:+.1e} | {r['dissipation_error']:+.1e} | {r['energy_created_rel']:+.1e} "
                         f"| {r['cpu_s']:.1f} |")
        parts.append(head + "\n".join(lines) + "\n")
    if lc:
        parts.append("**libcosim against the fmpy master, both Jacobi with the rail's velocity in vC_in** (largest "
                     "differences over the run)\n\n"
                     "| step | force handed to the track | F [N] | y [m] | z_rail [m] | F_wheel [N] |\n"
                     "|---|---|---|---|---|---|\n" +
                     "".join(f"| {r['step']:g} s | {r['force']} | {r['max_abs_diff_F_N']:.1e} | {r['max_abs_diff_y_m']:.1e} "
                             f"| {r['max_abs_diff_z_rail_m']:.1e} | {r['max_abs_diff_F_wheel_N']:.1e} |\n" for r in lc))
    path.write_text("\n".join(parts))


def plot(rows, keep, sol, system, targets, stop_time, me_rows=()):
    """Draw the figures into each (folder, dpi) of targets."""
    plot_errors(rows, targets, me_rows)
    plot_traces(keep, sol, targets, stop_time)


def plot_errors(rows, targets, me_rows=()):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    metrics_ = [("force_error", "force error  max|F - F_ref| / W"),
                ("mean_force_error", "mean-force error  max|F_mean - F_mean,ref| / W"),
                ("energy_created_rel", "|energy created by the coupling| / energy dissipated\n(open: negative, the coupling dissipates)")]
    styles = {"GS hold": "o-", "GS ramp": "s-", "GS track first": "d:", "Jacobi": "^--", "Jacobi ramp": "v--",
              "FMI 3.0 contact first": "x-.", "FMI 3.0 early return": "+-."}
    for ax, (key, title) in zip(axes, metrics_):
        for label, *_ in COUPLINGS:
            pts = [(r["step"], r[key]) for r in rows
                   if r["coupling"] == label and key in r and np.isfinite(r[key])]
            if not pts:
                continue
            x, y = map(np.array, zip(*pts))
            color = "C0" if label.endswith("F_mean") else "C3"
            style = styles[label.split(",")[0]]
            ax.loglog(x, np.abs(y), style, color=color, alpha=0.9, label=label,
                      mfc="none" if label.startswith("Jacobi") else color)
            if np.any(y < 0):
                ax.loglog(x[y < 0], -y[y < 0], style[0], color=color, mfc="white")
        for r, ls in zip(me_rows, (":", "--", "-.")):
            if key != "energy_created_rel":  # Model Exchange creates none
                ax.axhline(abs(r[key]), color="k", ls=ls, lw=0.8, label=f"Model Exchange, rtol {r['rtol']:g}")
        ax.set_xlabel("communication step [s]")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Vehicle-track co-simulation and Model Exchange against the monolithic reference "
                 "(errors above 1: unstable)")
    fig.tight_layout()
    for folder, dpi in targets:
        fig.savefig(folder / "errors.png", dpi=dpi)
    plt.close(fig)


def plot_traces(keep, sol, targets, stop_time):
    """Contact force over the stretch with the largest force: reference and co-simulations."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    tg = np.linspace(0, stop_time, 200001)
    Fg = sol.force(tg)
    tc = tg[np.argmax(Fg)]
    win = (max(tc - 2e-3, 0.0), min(tc + 2e-3, stop_time))
    sel = (tg >= win[0]) & (tg <= win[1])
    fig, axes = plt.subplots(1, 2, figsize=(14, 4.5), sharey=True)
    for ax, h in zip(axes, (1e-5, 1e-4)):
        ax.plot(tg[sel] * 1e3, Fg[sel] / 1e3, "k-", lw=2, label="monolithic reference")
        for label, color in (("GS hold, F", "C3"), ("GS hold, F_mean", "C0"), ("GS ramp, F_mean", "C2")):
            r = keep.get((label, h))
            if r is None:
                continue
            s = (r["t"] >= win[0]) & (r["t"] <= win[1])
            ax.step(r["t"][s] * 1e3, r["contact.F"][s] / 1e3, where="post", color=color, lw=1, label=label)
        ax.set_title(f"communication step {h:g} s")
        ax.set_xlabel("time [ms]")
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("contact force F [kN]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    for folder, dpi in targets:
        fig.savefig(folder / "traces.png", dpi=dpi)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=str(master.build_dir()))
    ap.add_argument("--out", default=str(HERE / "results"))
    ap.add_argument("--stop-time", type=float, default=parameters.STOP_TIME)
    ap.add_argument("--quick", action="store_true", help="three steps, 30 ms")
    ap.add_argument("--excitation", type=float, nargs=2, metavar=("A", "F"),
                    help="the contact FMU's internal harmonic instead of the roughness profile")
    ap.add_argument("--gallery", action="store_true", help="small copies of the figures in doc/")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    steps, stop = STEPS, a.stop_time
    if a.quick:
        steps, stop = [1e-5, 3e-5, 1e-4], min(stop, 0.03)
    profile = None
    if not a.excitation:
        profile = out / "profile.txt"
        roughness.write(profile, *roughness.profile(**parameters.ROUGHNESS))
    system, sol = run_reference(profile, a.excitation, stop)
    me_rows, _ = me_sweep(system, sol, [1e-8] if a.quick else ME_RTOLS, stop, profile, a.excitation, a.build)
    write_csv(out / "model_exchange.csv", me_rows)
    rows, keep = sweep(system, sol, steps, COUPLINGS, stop, profile, a.excitation, a.build)
    write_csv(out / "summary.csv", rows)
    # libcosim steps with the outputs of the last communication point (Jacobi), the rail extrapolated
    # with its velocity (vC_in): compare it with the fmpy master on the same scheme where that is stable
    # (2e-6 s) and where it is not (1e-5 s, F_mean)
    lc = compare_libcosim([2e-6, 1e-5] if not a.quick else [1e-5], stop, profile, a.excitation, a.build)
    write_csv(out / "libcosim.csv", lc)
    markdown(rows, lc, out / "summary.md", me_rows, system.cpu_s)
    targets = [(out, 110)]
    if a.gallery:
        (HERE / "doc").mkdir(exist_ok=True)
        targets.append((HERE / "doc", 70))
    plot(rows, keep, sol, system, targets, stop, me_rows)
    print(f"written: {out}")


if __name__ == "__main__":
    main()
