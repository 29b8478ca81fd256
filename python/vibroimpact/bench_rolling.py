"""The cost of rolling over a sampled rail, for `vibroimpact bench --only rolling` (and the full suite).

The paper's wheel (R1 = 0.475 m, Hertz, P = 40 kN = 10 m g) rolls at V = 30 m/s for 0.1 s over a periodic
corrugation h = A cos(2 pi x / L), L = 50 mm, A = 20 um, given as a table of WAVES wavelengths (1 m of rail)
sampled with 21 ... 20001 rows per wavelength (20 ... 20000 intervals), rtol 1e-8, communication steps
of 1 ms. Each table is rolled over with every profile_interpolation the FMU has (linear: the exact
polyline; cubic: the spline through the rows), in Co-Simulation (the C driver tools/bench_driver.c: the
whole run, from fmi2Instantiate through loading the table to the last step) and in Model Exchange
(fmpy's own CVode driver, fmpy.simulate_fmu, from Python). The CPU times are the minimum of the repeats,
the runs of one table size alternated with those of the others, so that the ratios to the 21-row table
come from one run of the command. The peak force is the largest F_peak at the communication points in
Co-Simulation (the largest force over each step), the largest F at the communication points in Model
Exchange; its convergence with the sampling is the relative difference to the densest table's.
"""
import math
import time

import numpy as np

WAVELENGTH = 0.05  # m
AMPLITUDE = 2e-5  # m
WAVES = 20  # wavelengths in the table (1 m of rail), repeated with profile_periodic
ROWS = (21, 201, 2001, 20001)  # rows per wavelength, both ends counted
V = 30.0  # m/s
T_STOP = 0.1  # s
H = 1e-3  # s, communication step
RTOL = 1e-8
ME_CAP_S = 60.0  # a Model Exchange run whose estimate (from the table before it) exceeds this is left out
INTERPOLATIONS = {"linear": 1, "cubic": 2}
TARGETS = {2001: 2.0, 20001: 5.0}  # the spline's CPU at these rows per wavelength / the 21-row table's, at most
PEAK_TARGET = 1e-4  # the spline's peak force at 2001 rows against 20001 rows, relative


def table(rows):
    """(x, h) [m] of the table of WAVES wavelengths at `rows` rows per wavelength."""
    x = np.linspace(0.0, WAVES * WAVELENGTH, WAVES * (rows - 1) + 1)
    h = AMPLITUDE * np.cos(2 * np.pi * x / WAVELENGTH)
    h[-1] = h[0]
    return x, h


def corrugation(path, rows):
    """Write the table of WAVES wavelengths at `rows` rows per wavelength, each number as Python's repr
    writes it (the shortest that reads back to the same double, as `vibroimpact rolling` writes its
    table)."""
    x, h = table(rows)
    path.write_text("".join(f"{a!r} {b!r}\n" for a, b in zip(x.tolist(), h.tolist())))


def passed(rows):
    """(rows, kinks of the polyline's yb) the wheel passes in the run. The corrugation curves less than
    the wheel (A (2 pi/L)^2 < 1/R1), so the wheel follows every segment and yb has a kink at each
    concave row, where the slope grows by more than vi_profile.h's VI_PROFILE_KINK_SLOPE (1e-9); the
    table is passed V T_STOP / (its length) times."""
    x, h = table(rows)
    slope = np.diff(h) / np.diff(x)
    jumps = np.diff(np.append(slope, slope[0]))  # at rows 1 .. n-1, the last one the seam
    times = V * T_STOP / (x[-1] - x[0])
    return times * (len(x) - 1), times * int(np.sum(jumps > 1e-9))


def params(path, interpolation):
    p = dict(contact_model=1, profile_file=str(path), V=V, profile_periodic=1, rtol=RTOL)
    if interpolation != "linear":
        p["profile_interpolation"] = INTERPOLATIONS[interpolation]
    return p


def cs_run(fmu, path, interpolation):
    """(CPU [s], peak force [N], CPU of the initialization [s]: loading the table, right-hand-side
    evaluations) of one Co-Simulation run through the C driver."""
    vrs = ",".join(str(fmu.vars[n].valueReference) for n in ("y", "v", "F_peak", "delta", "mode", "n_impacts"))
    saved, fmu.vrs = fmu.vrs, vrs
    try:
        fig, samples = fmu.run(params(path, interpolation), T_STOP, 0.0, 1, h=H)
    finally:
        fmu.vrs = saved
    if fig is None:
        return math.nan, math.nan, math.nan, math.nan
    return fig["cpu_s"], float(samples[:, 3].max()), fig["init_s"], fig["rhs"]


def _quiet(*_):
    """fmpy's logger that prints nothing (the Hertz runs exceed F_Y: the FMU warns once a run)."""


def me_run(fmu, path, interpolation):
    """(CPU [s], peak force [N], nan, nan) of one Model Exchange run through fmpy's CVode driver."""
    from fmpy import simulate_fmu
    start = time.process_time()
    r = simulate_fmu(str(fmu.path), fmi_type="ModelExchange", solver="CVode", stop_time=T_STOP,
                     relative_tolerance=RTOL, output_interval=H, start_values=params(path, interpolation),
                     output=["F"], record_events=False, model_description=fmu.md, logger=_quiet)
    return time.process_time() - start, float(np.max(r["F"])), math.nan, math.nan


def measure(fmu, work, repeat):
    """{(interface, interpolation, rows): (CPU, peak, CPU of the initialization, rhs evaluations)}: the
    minimum CPUs of `repeat` rounds, each round running every table once."""
    names = [i for i in INTERPOLATIONS if i == "linear" or "profile_interpolation" in fmu.vars]
    paths = {}
    for rows in ROWS:
        paths[rows] = work / f"corrugation_{rows}.txt"
        corrugation(paths[rows], rows)
    res = {}
    for interface, run in (("CS", cs_run), ("ME", me_run)):
        for name in names:
            for _ in range(repeat):
                estimate = 0.0  # s, the CPU of the table before, scaled by the rows
                for k, rows in enumerate(ROWS):
                    key = (interface, name, rows)
                    if interface == "ME" and estimate > ME_CAP_S:
                        res.setdefault(key, (math.nan,) * 4)
                        continue
                    cpu, peak, init, rhs = run(fmu, paths[rows], name)
                    old = res.get(key, (math.inf, peak, init, rhs))
                    res[key] = (min(old[0], cpu), peak, min(old[2], init), rhs)  # ME: init nan, min(nan, nan) nan
                    estimate = cpu * ROWS[min(k + 1, len(ROWS) - 1)] / rows
    return res


def report(out, res, repeat):
    """The table of measure's results and the ratios of the CPU to the 21-row table's: with the same
    interpolation, and with the exact polyline's (what the rail cost without profile_interpolation)."""
    out("### Rolling over a sampled rail: the cost of the rows\n")
    out(f"The wheel of the paper (Hertz) at V = {V:g} m/s over a corrugation of wavelength {1e3 * WAVELENGTH:g} mm and "
        f"amplitude {1e6 * AMPLITUDE:g} um, a periodic table of {WAVES} wavelengths at 21 ... 20001 rows per "
        f"wavelength, {T_STOP:g} s simulated, rtol {RTOL:g}, communication steps of {1e3 * H:g} ms. CPU: the minimum of "
        f"{repeat} rounds; CS: the C driver, loading the table included; ME: fmpy's CVode driver. Peak force: CS "
        "the largest F_peak, ME the largest F at the communication points; 'to densest': its relative difference "
        "to that of the densest table run with the same interpolation. CS initialization: from fmi2Instantiate to "
        "the end of fmi2ExitInitializationMode, reading the table and building yb; rhs: the right-hand-side "
        "evaluations the FMU counts (CS).\n")
    out("| interface | profile_interpolation | rows per wavelength | rows | CPU [s] | of which initialization [s] "
        "| rhs | CPU / 21 rows | CPU / 21 rows linear | peak force [kN] | to densest |")
    out("|---|---|---|---|---|---|---|---|---|---|---|")
    for (interface, name, rows), (cpu, peak, init, rhs) in res.items():
        base, linear = res[interface, name, ROWS[0]][0], res[interface, "linear", ROWS[0]][0]
        densest = [v[1] for k, v in res.items() if k[:2] == (interface, name) and not math.isnan(v[0])][-1]
        if math.isnan(cpu):
            out(f"| {interface} | {name} | {rows} | {WAVES * (rows - 1) + 1} | left out (estimated > {ME_CAP_S:g} s) "
                "| | | | | | |")
            continue
        out(f"| {interface} | {name} | {rows} | {WAVES * (rows - 1) + 1} | {cpu:.4f} | "
            f"{'-' if math.isnan(init) else format(init, '.4f')} | {'-' if math.isnan(rhs) else int(rhs)} | "
            f"{cpu / base:.2f} | {cpu / linear:.2f} | "
            f"{peak / 1e3:.4f} | {abs(peak / densest - 1):.1e} |")
    out("")
    costs(out, res)
    for (interface, name, rows), (cpu, *_) in res.items():
        if rows == ROWS[0]:
            linear = res[interface, "linear", rows][0]
            r2, r3 = (res[interface, name, n][0] for n in ROWS[2:])
            out(f"- {interface}, {name}: 2001 / 21 rows {r2 / cpu:.2f}, 20001 / 21 rows {r3 / cpu:.2f}; against the "
                f"21-row polyline {r2 / linear:.2f} and {r3 / linear:.2f}")
    out("")
    verdicts(out, res)


def verdicts(out, res):
    """The spline against TARGETS (against the 21-row spline and the 21-row polyline) and PEAK_TARGET."""
    if ("CS", "cubic", ROWS[0]) not in res:
        return
    for interface in ("CS", "ME"):
        cubic, linear = res[interface, "cubic", ROWS[0]][0], res[interface, "linear", ROWS[0]][0]
        parts = []
        for rows, bound in TARGETS.items():
            cpu = res[interface, "cubic", rows][0]
            parts.append(f"{rows} / 21 rows at most {bound:g}: {cpu / cubic:.2f} "
                         f"({'met' if cpu <= bound * cubic else 'missed'}; against the polyline's {cpu / linear:.2f}, "
                         f"{'met' if cpu <= bound * linear else 'missed'})")
        peak = abs(res[interface, "cubic", 2001][1] / res[interface, "cubic", 20001][1] - 1)
        parts.append(f"peak force 2001 against 20001 rows within {PEAK_TARGET:g}: {peak:.1e} "
                     f"({'met' if peak <= PEAK_TARGET else 'missed'})")
        out(f"Target, {interface}, cubic: " + "; ".join(parts) + ".")
    out("")


def costs(out, res):
    """The cost per row passed and per kink of the polyline: the CPU of a run over it less that of the
    spline through the same rows (which has no kink), divided by the kinks passed."""
    out("Cost per row passed and per kink: rows and kinks of the polyline the wheel passes in the run, CPU per row "
        "passed, and (linear - cubic) / kinks passed.\n")
    out("| interface | rows per wavelength | rows passed | kinks passed | linear per row [us] | cubic per row [us] "
        "| per kink [us] |")
    out("|---|---|---|---|---|---|---|")
    for (interface, name, rows), (cpu, *_) in res.items():
        cubic = res.get((interface, "cubic", rows), (math.nan,))[0]
        if name != "linear" or math.isnan(cpu):
            continue
        n_rows, n_kinks = passed(rows)
        out(f"| {interface} | {rows} | {n_rows:.0f} | {n_kinks:.0f} | {1e6 * cpu / n_rows:.3g} | "
            f"{1e6 * cubic / n_rows:.3g} | {1e6 * (cpu - cubic) / n_kinks:.3g} |")
    out("")


def rolling(out, fmu, work, repeat):
    report(out, measure(fmu, work, repeat), repeat)
