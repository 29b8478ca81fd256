"""The figures of the commands, as matplotlib Figures built from their data: a paper scenario, the
overview of every scenario, the rolling runs, one sweep's response and bifurcation diagram, the
diagrams' up/down comparisons, and the benchmark's work-precision and cost plots. Nothing is
written here: the commands save what these functions return (save()).

matplotlib is imported when a figure is made, not with this module; pyplot() chooses the
non-interactive Agg backend unless pyplot is already in use.
"""
import sys

import numpy as np


def pyplot():
    """matplotlib.pyplot, with the Agg backend when no pyplot was imported before (files, no windows)."""
    if "matplotlib.pyplot" not in sys.modules:
        import matplotlib
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save(fig, path, dpi):
    """Write fig to path (the folder must exist) and close it."""
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)
    return path


# ---- the paper's scenarios (vibroimpact paper) ---------------------------------------------------------

def draw_positions(ax, r, lepp, lw=1.0):
    """Paper style: 1 thin, the platform yC(t); 2 bold, the mass y(t); LEPP (Fig. 6) adds the
    platform's unloaded surface yC - delta_p (the indentation is then the gap between it and y)."""
    ms = 1e3 * r["time"]
    ax.plot(ms, 1e3 * r["yC"], lw=0.5 * lw, color="k", label="1: platform $y_C(t)$")
    if lepp:
        ax.plot(ms, 1e3 * (r["yC"] - r["delta_p"]), lw=0.5 * lw, color="C2", label="2: $y_C - \\delta_p$")
    ax.plot(ms, 1e3 * r["y"], lw=1.3 * lw, color="C0", label=f"{3 if lepp else 2}: mass $y(t)$")
    ax.set_ylabel("position [mm]")


def scenario_figure(scenario, r, s):
    """One scenario: positions against time, the force against time, the force against the indentation.
    r: the run's outputs by name; s: its summary (paper.summarize)."""
    plt = pyplot()
    lepp = scenario.full.get("contact_model") == 3
    fig = plt.figure(figsize=(10, 7))
    grid = fig.add_gridspec(2, 2, height_ratios=[1.2, 1], width_ratios=[1.6, 1])
    ax = fig.add_subplot(grid[0, :])
    draw_positions(ax, r, lepp)
    ax.set_xlabel("time [ms]")
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"{scenario.title}\n{s['n_impacts']} impacts, max force {s['F_max_kN']:.0f} kN, "
                 f"W_plastic {s['W_plastic_J']:.3g} J", fontsize=10)
    ax = fig.add_subplot(grid[1, 0])
    ax.plot(1e3 * r["time"], 1e-3 * r["F"], lw=0.7, color="C3")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("contact force F [kN]")
    ax = fig.add_subplot(grid[1, 1])
    ax.plot(1e6 * r["delta"], 1e-3 * r["F"], lw=0.5, color="C3")
    ax.set_xlim(left=min(0.0, 1e6 * r["delta"][r["F"] > 0].min(initial=0.0)))
    ax.set_xlabel(r"indentation $\delta$ [$\mu$m]")
    ax.set_ylabel("F [kN]")
    fig.tight_layout()
    return fig


def overview_figure(runs):
    """Every scenario's positions, one panel each. runs: name -> (scenario, outputs by name)."""
    plt = pyplot()
    names = list(runs)
    cols = 3
    rows = -(-len(names) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(13, 2.6 * rows), squeeze=False)
    for ax, name in zip(axes.flat, names):
        scenario, r = runs[name]
        draw_positions(ax, r, scenario.full.get("contact_model") == 3, lw=0.7)
        ax.set_title(scenario.title, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.yaxis.label.set_size(7)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    fig.suptitle("VibroImpact FMU: the paper's scenarios (thin: platform, bold: mass; time in ms)", fontsize=10)
    fig.tight_layout()
    return fig


# ---- rolling over a corrugated rail (vibroimpact rolling) ----------------------------------------------

def rolling_figure(profile, runs, passing):
    """profile: (s [m], h(s) [m], yb(s) [m], R1 [m]); runs: case -> (V [m/s], outputs by name);
    passing: case -> passing frequency [Hz]."""
    plt = pyplot()
    s, h, yb, R1 = profile
    fig, axes = plt.subplots(len(runs) + 1, 2, figsize=(12, 3 * (len(runs) + 1)))
    ax = axes[0, 0]
    ax.plot(1e3 * s, 1e6 * h, lw=0.8, color="0.5", label="profile h(x)")
    ax.plot(1e3 * s, 1e6 * yb, lw=1.2, color="k", label=f"constraint yb(x), R1 = {R1} m")
    ax.set_xlabel("x [mm]"), ax.set_ylabel("[um]"), ax.legend(fontsize=8)
    ax.set_title("corrugation h(x) and the constraint yb(x) the wheel's lowest point follows", fontsize=9)
    axes[0, 1].axis("off")
    for i, (name, (V, r)) in enumerate(runs.items(), start=1):
        ms = 1e3 * r["time"]
        a, b = axes[i]
        a.plot(ms, 1e3 * r["yC"], lw=0.5, color="k", label="1: rail under the wheel $y_C$")
        a.plot(ms, 1e3 * r["y"], lw=1.2, color="C0", label="2: wheel $y$")
        a.set_ylabel("[mm]"), a.legend(fontsize=7, loc="lower left")
        a.set_title(f"{name} the contact resonance: V = {V:.2f} m/s, passing {passing[name]:g} Hz", fontsize=9)
        b.plot(ms, 1e-3 * r["F"], lw=0.8, color="C3")
        b.set_ylabel("F [kN]")
        for ax in (a, b):
            ax.set_xlabel("t [ms]")
    fig.tight_layout()
    return fig


# ---- sweeps (vibroimpact sweep, vibroimpact diagrams) --------------------------------------------------

UNITS = {"f": "Hz", "a": "m", "P": "N", "m": "kg", "Y": "Pa", "g": "m/s$^2$", "F_ext": "N", "yC_in": "m",
         "v0": "m/s", "R1": "m", "R2": "m", "E1": "Pa", "E2": "Pa"}
MAX_LINES = 10   # more combinations of the other grids than this: drawn without a legend


def axis_label(name):
    return f"{name} [{UNITS[name]}]" if name in UNITS else name


def groups(cols, names):
    """[(label, key)], one per combination of the grid variables after the first (key: name -> value)."""
    others = names[1:]
    keys = sorted(set(zip(*[cols[n] for n in others]))) if others else [()]
    return [(", ".join(f"{n}={v:g}" for n, v in zip(others, k)), dict(zip(others, k))) for k in keys]


def select(cols, key):
    """Row mask of a table (sweep.csv or poincare.csv columns) for one key of groups()."""
    n = len(next(iter(cols.values()))) if cols else 0
    return np.all([np.asarray(cols[name]) == v for name, v in key.items()] + [np.ones(n, bool)], axis=0)


def draw_response(axes, cols, x_name, mask=None, label="", **style):
    """Three axes: force (max solid, min dashed) [kN], largest separation [mm], contact fraction."""
    mask = np.ones(len(cols[x_name]), bool) if mask is None else mask
    order = np.argsort(cols[x_name][mask], kind="stable")
    x = cols[x_name][mask][order]
    get = lambda k: cols[k][mask][order]  # noqa: E731
    line, = axes[0].plot(x, get("F_max") / 1e3, label=label, **style)
    axes[0].plot(x, get("F_min") / 1e3, ls="--", lw=0.8, color=line.get_color(), marker=None)
    axes[1].plot(x, get("sep_max") * 1e3, color=line.get_color(), **{k: v for k, v in style.items() if k != "color"})
    axes[2].plot(x, get("contact_fraction"), color=line.get_color(),
                 **{k: v for k, v in style.items() if k != "color"})
    bad = np.array([s != "ok" for s in cols["status"]])[mask][order]
    if bad.any():
        axes[0].plot(x[bad], np.zeros(bad.sum()), "x", color="red", label="failed")
    axes[0].set_ylabel("force [kN]\nmax (solid), min (dashed)")
    axes[1].set_ylabel("largest\nseparation [mm]")
    axes[2].set_ylabel("contact fraction")
    axes[2].set_ylim(-0.05, 1.05)
    return line


def draw_bifurcation(ax, poincare, x_name, mask=None, label="", **style):
    """Poincare indentation against the swept variable, in um (mm when it exceeds 10 mm)."""
    mask = np.ones(len(poincare.get(x_name, [])), bool) if mask is None else mask
    if x_name not in poincare or not mask.any():
        return
    style = {"s": 2, "lw": 0, **style}
    big = np.nanmax(np.abs(poincare["delta"])) > 1e-2
    scale, unit = (1e3, "mm") if big else (1e6, "$\\mu$m")
    ax.scatter(poincare[x_name][mask], poincare["delta"][mask] * scale, label=label, **style)
    ax.set_ylabel(f"indentation at phase 0 [{unit}]")


def sweep_title(sweep):
    return (sweep.title or " ".join(f"{k}={v}" for k, v in sweep.fixed.items())) \
        + (f" ({sweep.direction}-sweep)" if sweep.direction else "")


def response_figure(sweep, cols):
    """One sweep's response against its first grid variable; cols: sweep.csv's columns."""
    plt = pyplot()
    x_name = sweep.names[0]
    keys = groups(cols, sweep.names)
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 8))
    for label, key in keys:
        draw_response(axes, cols, x_name, select(cols, key), label=label, marker=".", ms=4, lw=1)
    axes[-1].set_xlabel(axis_label(x_name))
    if x_name in sweep.log_axes:
        axes[-1].set_xscale("log")
    if 1 < len(keys) <= MAX_LINES:
        axes[0].legend(fontsize=7)
    axes[0].set_title(f"Response: {sweep_title(sweep)}", fontsize=9)
    fig.tight_layout()
    return fig


def bifurcation_figure(sweep, cols, poincare):
    """One sweep's Poincare indentation against its first grid variable."""
    plt = pyplot()
    x_name = sweep.names[0]
    keys = groups(cols, sweep.names)
    fig, ax = plt.subplots(figsize=(8, 5))
    for label, key in keys if poincare else []:
        draw_bifurcation(ax, poincare, x_name, select(poincare, key), label=label)
    ax.set_xlabel(axis_label(x_name))
    if x_name in sweep.log_axes:
        ax.set_xscale("log")
    if 1 < len(keys) <= MAX_LINES:
        ax.legend(fontsize=7, markerscale=4)
    ax.set_title(f"Bifurcation diagram (Poincare section at phase 0, after {sweep.transient:g} s): "
                 f"{sweep_title(sweep)}", fontsize=9)
    fig.tight_layout()
    return fig


DIRECTIONS = [("up", "C0", "^"), ("down", "C1", "v")]   # continuation direction, colour, marker


def diagrams_response_figure(runs, fc, panels, stop_time, transient):
    """The diagrams' response: one column per (amplitude, law) panel, up and down sweeps in each.
    runs: (law, amplitude label, direction) -> (sweep.csv columns, poincare columns); fc: law ->
    f_contact [Hz]; panels: [(law, law title, amplitude label, a [m])]."""
    plt = pyplot()
    fig, axes = plt.subplots(3, len(panels), figsize=(4.5 * len(panels), 8.5), sharex="col", squeeze=False)
    for j, (law, title, amp, a) in enumerate(panels):
        col = axes[:, j]
        for direction, color, marker in DIRECTIONS:
            cols, _ = runs[law, amp, direction]
            draw_response(col, cols, "f", label=f"{direction}-sweep", color=color, marker=marker, ms=3, lw=0.8)
        for ax in col:
            ax.axvline(fc[law], color="k", lw=0.6, ls=":")
        col[0].set_title(f"{title}, a = {a * 1e6:g} $\\mu$m\n(dotted: f_contact = {fc[law]:.1f} Hz)", fontsize=9)
        col[-1].set_xlabel("excitation frequency f [Hz]")
        if j:
            for ax in col:
                ax.set_ylabel("")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Amplitude-frequency response: continuation up and down in f "
                 f"({stop_time:g} s per point, statistics after {transient:g} s)", fontsize=10)
    fig.tight_layout()
    return fig


def diagrams_bifurcation_figure(runs, fc, panels):
    """The diagrams' bifurcation diagrams, one panel per (amplitude, law), up and down sweeps in each."""
    plt = pyplot()
    laws = list(dict.fromkeys(p[0] for p in panels))
    amps = list(dict.fromkeys(p[2] for p in panels))
    fig, axes = plt.subplots(len(amps), len(laws), figsize=(12, 4.2 * len(amps)), squeeze=False)
    for law, title, amp, a in panels:
        ax = axes[amps.index(amp), laws.index(law)]
        for direction, color, marker in DIRECTIONS:
            _, pc = runs[law, amp, direction]
            draw_bifurcation(ax, pc, "f", label=f"{direction}-sweep", color=color, s=3 if direction == "up" else 2,
                             marker=marker, alpha=0.7)
        ax.axvline(fc[law], color="k", lw=0.6, ls=":")
        ax.set_title(f"{title}, a = {a * 1e6:g} $\\mu$m", fontsize=9)
        ax.set_xlabel("excitation frequency f [Hz]")
        ax.legend(fontsize=7, markerscale=3)
    fig.suptitle("Bifurcation diagrams: indentation once per excitation period (phase 0) after the transient",
                 fontsize=10)
    fig.tight_layout()
    return fig


# ---- the benchmark (vibroimpact bench) -----------------------------------------------------------------

SOLVER_COLORS = dict(bdf="tab:blue", adams="tab:orange", dop853="tab:green", auto="tab:purple")


def work_precision_figure(results, rtols, cases, solvers, bound):
    """CPU time against error per case: every solver, the Python reference, RK4. results: bench's."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(cases), figsize=(5.5 * len(cases), 5), squeeze=False)
    axes = axes[0]
    for ax, (case, res) in zip(axes, (c for c in results.items() if c[0] in cases)):
        for name in solvers:
            pts = [(res["fmu"][name, r][0], res["fmu"][name, r][1]) for r in rtols if res["fmu"][name, r][0]]
            ax.loglog([1e3 * c for c, _ in pts], [max(e, 1e-16) for _, e in pts], "o-", color=SOLVER_COLORS[name],
                      label=f"FMU {name}")
        pts = [res["py"][r] for r in rtols if res["py"][r][0] is not None]
        if pts:
            ax.loglog([1e3 * c for c, _ in pts], [max(e, 1e-16) for _, e in pts], "s--", color="k",
                      label="Python reference (SciPy DOP853)")
        if res["rk4"]:
            pts = list(res["rk4"].values())
            ax.loglog([1e3 * c for c, _ in pts], [max(e, 1e-16) for _, e in pts], "x:", color="tab:red",
                      label="RK4, no event location")
        ax.axhline(bound, color="gray", lw=0.8)
        ax.set_title(cases[case]["title"], fontsize=10)
        ax.set_xlabel("CPU [ms]")
        ax.set_ylabel("error" + (" (energy, restitution)" if case == "drop" else " / range of y"))
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    return fig


def cost_figure(results, solvers):
    """Cost per step against the communication step, against simulated time, against impacts."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5))
    steps = sorted({h for (_, h) in results["per_step"]})
    for name in solvers:
        axes[0].loglog(steps, [results["per_step"][name, h] for h in steps], "o-", color=SOLVER_COLORS[name],
                       label=name)
        axes[1].plot(results["time_spans"], [1e3 * c for c in results["time"][name]], "o-", color=SOLVER_COLORS[name], label=name)
        pts = results["impacts"][name]
        axes[2].plot([a for a, _ in pts], [1e3 * c for _, c in pts], "o-", color=SOLVER_COLORS[name], label=name)
    axes[0].set(xlabel="communication step [s]", ylabel="CPU per fmi2DoStep [us]", title="fig4b, 10 ms")
    axes[1].set(xlabel="simulated time [s]", ylabel="CPU [ms]", title="fig4b, matched rtol")
    axes[2].set(xlabel="impacts", ylabel="CPU [ms]", title="Hertz, 0.1 s, rtol 1e-8")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig
