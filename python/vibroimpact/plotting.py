"""The figures of the commands, as matplotlib Figures built from their data: a paper scenario, the
overview of every scenario, the rolling runs, one sweep's response and bifurcation diagram, the
diagrams' up/down comparisons, and the benchmark's work-precision and cost plots. Nothing is
written here: the commands save what these functions return (save()).

matplotlib is imported when a figure is made, not with this module; pyplot() chooses the
non-interactive Agg backend unless pyplot is already in use.
"""
import sys
import textwrap

import numpy as np


def pyplot():
    """matplotlib.pyplot, with the Agg backend when no pyplot was imported before (files, no windows)."""
    if "matplotlib.pyplot" not in sys.modules:
        import matplotlib
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def wrap(text, width):
    """text broken into lines of at most width characters, each line of it on its own and into lines of
    about equal length (a title of 80 characters in two of 40 or so, not one of 60 and one of 20)."""
    def balanced(line):
        n = -(-len(line) // width)
        return textwrap.fill(line, min(width, -(-len(line) // n) + 8)) if n > 1 else line
    return "\n".join(balanced(line) for line in text.split("\n"))


def figure_legend(fig, axes, loc="outside lower center", ncols=4, **style):
    """One legend for the figure, outside its panels: every labelled line and scatter of axes, once per label."""
    handles = {}
    for ax in axes:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    if handles:
        fig.legend(list(handles.values()), list(handles), loc=loc, ncols=min(ncols, len(handles)), **style)


def save(fig, path, dpi):
    """Write fig to path (the folder must exist; the file replaced only once complete: files.save_figure)
    and close it."""
    from .files import save_figure
    save_figure(fig, path, dpi)
    pyplot().close(fig)
    return path


# ---- a mass between two walls (vibroimpact laws: the upper stop) -----------------------------------------

def draw_walls(ax, walls, masses, f):
    """The lower wall yC (thin, black), the upper wall yC + gap (thin, grey) from `walls` (a trace: time,
    yC, gap) and the mass of each (label, trace, colour, line style) of `masses`, in mm against the
    platform's cycles t f; each contact onset (n_impacts, n_impacts_upper rising) marked on the mass in
    its colour, ^ on the lower wall, v on the upper one."""
    cyc = walls["time"] * f
    ax.plot(cyc, 1e3 * walls["yC"], color="k", lw=0.8, label="lower wall $y_C$")
    ax.plot(cyc, 1e3 * (walls["yC"] + walls["gap"]), color="0.5", lw=0.8, label="upper wall $y_C$ + gap")
    for label, tr, color, ls in masses:
        t, y = tr["time"] * f, 1e3 * tr["y"]
        ax.plot(t, y, color=color, ls=ls, lw=1.3, label=f"sphere $y$, {label}")
        for key, marker, wall in (("n_impacts", "^", "lower"), ("n_impacts_upper", "v", "upper")):
            hit = np.nonzero(np.diff(tr[key]) > 0)[0] + 1
            ax.scatter(t[hit], y[hit], marker=marker, s=36, color=color, edgecolors="k", linewidths=0.5, zorder=3,
                       label=f"impact on the {wall} wall, {label}")
    ax.set(xlabel="time [platform cycles]", ylabel="position [mm]")


# ---- the paper's scenarios (vibroimpact paper) ---------------------------------------------------------

POSITION_LINES = {   # what draw_positions draws: label, colour, line width against the figure's lw
    "platform": ("platform $y_C(t)$", "k", 0.5),
    "surface": ("platform's unloaded surface $y_C - \\delta_p$ (LEPP)", "C2", 0.5),
    "mass": ("mass $y(t)$", "C0", 1.3),
}


def draw_positions(ax, r, lepp, lw=1.0):
    """Paper style: thin, the platform yC(t); bold, the mass y(t); LEPP (Fig. 6) adds the platform's
    unloaded surface yC - delta_p (the indentation is then the gap between it and y)."""
    ms = 1e3 * r["time"]
    curves = [("platform", r["yC"])] + ([("surface", r["yC"] - r["delta_p"])] if lepp else []) + [("mass", r["y"])]
    for key, y in curves:
        label, color, width = POSITION_LINES[key]
        ax.plot(ms, 1e3 * y, lw=width * lw, color=color, label=label)
    ax.set_ylabel("position [mm]")


# the FMU's output `mode` (doc/model.md section 3): name, shade of its phases in the time plots
MODES = {0: ("free", "0.85"), 1: ("elastic (virgin curve)", "tab:blue"), 2: ("plastic loading", "tab:red"),
         3: ("elastic unload/reload", "tab:green"), 4: ("stick", "tab:orange")}
MODE_ALPHA = 0.18


def draw_modes(ax, r, label=True):
    """Shade each phase of the run by its mode (output `mode`: a phase from the sample where it is first
    seen to the next phase's first sample), over the axes' height, edged so that a phase shorter than a
    pixel still shows as a hairline; a legend entry per mode present (label=False: none)."""
    ms, mode = 1e3 * np.asarray(r["time"]), np.asarray(r["mode"]).astype(int)
    starts = np.concatenate([[0], np.flatnonzero(np.diff(mode)) + 1])
    ends = np.append(starts[1:], len(ms) - 1)
    for k, (name, color) in MODES.items():
        spans = [(ms[a], ms[b] - ms[a]) for a, b in zip(starts, ends) if mode[a] == k]
        if spans:
            ax.broken_barh(spans, (0, 1), transform=ax.get_xaxis_transform(), facecolor=color, edgecolor=color,
                           alpha=MODE_ALPHA, lw=0.6, label=f"mode {k}: {name}" if label else "_nolegend_")


def entries(mode, k):
    """How many phases of mode k the samples `mode` hold (a run that starts in it counts one)."""
    inside = np.asarray(mode).astype(int) == k
    return int(inside[0]) + int(np.count_nonzero(inside[1:] & ~inside[:-1]))


def scenario_title(scenario, r, s):
    """The title's figures: impacts (contact onsets: output n_impacts, so a run that never leaves the
    platform has none), the contact fraction, the plastic loadings (phases of mode 2: the force spikes
    of a run in contact), stick, the largest force and W_plastic."""
    contact = "in contact throughout" if s["contact_fraction"] >= 1 else \
        f"in contact {100 * s['contact_fraction']:.0f}% of the time"
    parts = [f"{s['n_impacts']} impacts ({contact})", f"{entries(r['mode'], 2)} plastic loadings"]
    if s["stick_fraction"] > 0:
        parts.append(f"stick {100 * s['stick_fraction']:.0f}%")
    parts += [f"max force {s['F_max_kN']:.0f} kN", f"W_plastic {s['W_plastic_J']:.3g} J"]
    return f"{scenario.title}\n" + ", ".join(parts)


def scenario_figure(scenario, r, s):
    """One scenario: positions against time, the force against time, the force against the indentation;
    the time plots shaded by mode. r: the run's outputs by name; s: its summary (paper.summarize)."""
    plt = pyplot()
    lepp = scenario.full.get("contact_model") == 3
    fig = plt.figure(figsize=(10, 7.5), layout="constrained")
    grid = fig.add_gridspec(2, 2, height_ratios=[1.2, 1], width_ratios=[1.6, 1])
    ax = fig.add_subplot(grid[0, :])
    draw_modes(ax, r)
    draw_positions(ax, r, lepp)
    ax.set_xlabel("time t [ms]")
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncols=4, fontsize=8, frameon=False)
    fig.suptitle(wrap(scenario_title(scenario, r, s), 110), fontsize=10)
    ax = fig.add_subplot(grid[1, 0])
    draw_modes(ax, r, label=False)
    ax.plot(1e3 * r["time"], 1e-3 * r["F"], lw=0.7, color="C3")
    ax.set_xlabel("time t [ms]")
    ax.set_ylabel("contact force F [kN]")
    ax = fig.add_subplot(grid[1, 1])
    ax.plot(1e6 * r["delta"], 1e-3 * r["F"], lw=0.5, color="C3")
    ax.set_xlim(left=min(0.0, 1e6 * r["delta"][r["F"] > 0].min(initial=0.0)))
    ax.set_xlabel(r"indentation $\delta$ [$\mu$m]")
    ax.set_ylabel("contact force F [kN]")
    return fig


def overview_figure(runs, cols=3):
    """Every scenario's positions, one panel each, on one time axis. runs: name -> (scenario, outputs by name)."""
    plt = pyplot()
    names = list(runs)
    rows = -(-len(names) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(13, 2.3 * rows + 1.0), sharex=True, squeeze=False,
                             layout="constrained")
    for ax, name in zip(axes.flat, names):
        scenario, r = runs[name]
        draw_positions(ax, r, scenario.full.get("contact_model") == 3, lw=0.7)
        ax.set_title(wrap(scenario.title, 62), fontsize=8)
        ax.tick_params(labelsize=7)
        ax.yaxis.label.set_size(7)
    for k, ax in enumerate(axes.flat):
        if k >= len(names):
            ax.remove()
        elif k + cols >= len(names):   # the lowest panel of its column
            ax.xaxis.set_tick_params(labelbottom=True)
            ax.set_xlabel("time t [ms]", fontsize=7)
    fig.suptitle("VibroImpact FMU: the paper's scenarios", fontsize=10)
    figure_legend(fig, axes.flat[:len(names)], loc="outside lower center", ncols=3, fontsize=8, frameon=False)
    return fig


# ---- rolling over a corrugated rail (vibroimpact rolling) ----------------------------------------------

def rolling_figure(profile, runs, passing):
    """profile: (s [m], h(s) [m], yb(s) [m], R1 [m]); runs: case -> (V [m/s], outputs by name);
    passing: case -> passing frequency [Hz]."""
    plt = pyplot()
    s, h, yb, R1 = profile
    fig = plt.figure(figsize=(12, 3 * (len(runs) + 1) + 0.5), layout="constrained")
    grid = fig.add_gridspec(len(runs) + 1, 2)
    ax = fig.add_subplot(grid[0, :])
    ax.plot(1e3 * s, 1e6 * h, lw=0.8, color="0.5", label="corrugation h(x)")
    ax.plot(1e3 * s, 1e6 * yb, lw=1.2, color="k", label="constraint yb(x)")
    ax.set_xlabel("position along the rail x [mm]")
    ax.set_ylabel(r"height [$\mu$m]")
    ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8)
    ax.set_title(f"The corrugation h(x) and the constraint yb(x) the lowest point of the wheel (R1 = {R1} m) "
                 "follows", fontsize=9)
    for i, (name, (V, r)) in enumerate(runs.items(), start=1):
        ms = 1e3 * r["time"]
        a, b = fig.add_subplot(grid[i, 0]), fig.add_subplot(grid[i, 1])
        a.plot(ms, 1e3 * r["yC"], lw=0.5, color="k", label="rail under the wheel $y_C$")
        a.plot(ms, 1e3 * r["y"], lw=1.2, color="C0", label="wheel $y$")
        a.set_ylabel("vertical position [mm]")
        a.set_title(f"{name} the contact resonance: V = {V:.2f} m/s, passing {passing[name]:g} Hz", fontsize=9)
        b.plot(ms, 1e-3 * r["F"], lw=0.8, color="C3", label="contact force F")
        b.set_ylabel("contact force F [kN]")
        for ax in (a, b):
            ax.set_xlabel("time t [ms]")
    figure_legend(fig, fig.axes[1:3], ncols=3, fontsize=8)
    return fig


# ---- sweeps (vibroimpact sweep, vibroimpact diagrams) --------------------------------------------------

# the quantity and unit of a start value a sweep may vary (others are named by their variable name)
QUANTITIES = {"f": ("excitation frequency", "Hz"), "a": ("excitation amplitude", "m"), "P": ("static load", "N"),
              "m": ("mass", "kg"), "Y": ("yield stress", "Pa"), "g": ("gravity", "m/s$^2$"),
              "F_ext": ("external force", "N"), "yC_in": ("platform position input", "m"),
              "v0": ("initial velocity", "m/s"), "R1": ("radius of body 1", "m"), "R2": ("radius of body 2", "m"),
              "E1": ("Young's modulus of body 1", "Pa"), "E2": ("Young's modulus of body 2", "Pa"),
              "nu1": ("Poisson's ratio of body 1", "1"), "nu2": ("Poisson's ratio of body 2", "1"),
              "theta_Y": ("yield factor", "1")}
MAX_LINES = 10   # more combinations of the other grids than this: one colour scale instead of a legend
FAILED = "failed point (no result; its reason is in sweep.csv)"


def axis_label(name):
    quantity, unit = QUANTITIES.get(name, ("start value", None))
    return f"{quantity} {name}" + (f" [{unit}]" if unit else "")


def x_variable(sweep):
    """The grid the figures draw along: a continuation's own; else the grid with the most values (the first of
    those), so that the others make few lines."""
    if sweep.direction:
        return sweep.names[0]
    return max(sweep.grids, key=lambda g: len(g[1]))[0]


def groups(cols, names, x_name):
    """[(label, key)], one per combination of the grid variables other than x_name (key: name -> value)."""
    others = [n for n in names if n != x_name]
    keys = sorted(set(zip(*[cols[n] for n in others]))) if others else [()]
    return [(", ".join(f"{n} = {v:g}{unit_of(n)}" for n, v in zip(others, k)), dict(zip(others, k))) for k in keys]


def unit_of(name):
    """ ' <unit>' of a start value QUANTITIES knows (dimensionless and unknown ones: '')."""
    unit = QUANTITIES.get(name, (None, "1"))[1]
    return "" if unit == "1" else f" {unit}"


def select(cols, key):
    """Row mask of a table (sweep.csv or poincare.csv columns) for one key of groups()."""
    n = len(next(iter(cols.values()))) if cols else 0
    return np.all([np.asarray(cols[name]) == v for name, v in key.items()] + [np.ones(n, bool)], axis=0)


def group_colors(fig, axes, sweep, keys):
    """A colour per group: the cycle with legend labels when there are few; else one colour scale over
    the first other variable, with a colour bar naming it (and no labels)."""
    if len(keys) <= MAX_LINES:
        return [(label if len(keys) > 1 else "", None) for label, _ in keys]
    from matplotlib import cm, colors
    name = next(iter(keys[0][1]))
    values = [k[name] for _, k in keys]
    norm = (colors.LogNorm if name in sweep.log_axes else colors.Normalize)(min(values), max(values))
    more = [n for n in keys[0][1] if n != name]
    fig.colorbar(cm.ScalarMappable(norm, "viridis"), ax=axes, label=axis_label(name)
                 + (f" (lines of one colour differ in {', '.join(more)})" if more else ""))
    return [("_nolegend_", cm.viridis(norm(k[name]))) for _, k in keys]


def draw_response(axes, cols, x_name, mask=None, label="", **style):
    """Three axes: force (max solid, min dashed) [kN], largest separation [mm], contact fraction."""
    mask = np.ones(len(cols[x_name]), bool) if mask is None else mask
    order = np.argsort(cols[x_name][mask], kind="stable")
    x = cols[x_name][mask][order]
    get = lambda k: cols[k][mask][order]  # noqa: E731
    line, = axes[0].plot(x, get("F_max") / 1e3, label=label, **style)
    rest = {k: v for k, v in style.items() if k != "color"}
    axes[0].plot(x, get("F_min") / 1e3, ls="--", lw=0.8, color=line.get_color(), marker=None)
    axes[1].plot(x, get("sep_max") * 1e3, color=line.get_color(), **rest)
    axes[2].plot(x, get("contact_fraction"), color=line.get_color(), **rest)
    axes[0].set_ylabel("contact force [kN]\nmax (solid), min (dashed)")
    axes[1].set_ylabel("largest\nseparation [mm]")
    axes[2].set_ylabel("contact fraction")
    axes[2].set_ylim(-0.05, 1.05)
    return line


def from_zero(axes):
    """Axes of magnitudes (force, separation) from zero once every line is drawn, when their data are not
    negative: a spread of a few per cent is drawn as a few per cent of the height."""
    for ax in axes:
        if ax.dataLim.y0 >= 0:
            ax.set_ylim(bottom=0)


def draw_failed(ax, cols, x_name):
    """The points that failed, as red crosses on the zero line of ax, with their legend label."""
    bad = np.array([s != "ok" for s in cols["status"]])
    if bad.any():
        ax.plot(cols[x_name][bad], np.zeros(bad.sum()), "x", color="red", ms=7, label=FAILED)


def draw_bifurcation(ax, poincare, x_name, mask=None, label="", **style):
    """Poincare indentation against the swept variable, in um (mm when it exceeds 1 mm)."""
    mask = np.ones(len(poincare.get(x_name, [])), bool) if mask is None else mask
    if x_name not in poincare or not mask.any():
        return
    style = {"s": 2, "lw": 0, **style}
    big = np.nanmax(np.abs(poincare["delta"])) > 1e-3
    scale, unit = (1e3, "mm") if big else (1e6, "$\\mu$m")
    ax.scatter(poincare[x_name][mask], poincare["delta"][mask] * scale, label=label, **style)
    ax.set_ylabel(f"indentation at phase 0 [{unit}]")


def sweep_title(sweep):
    return (sweep.title or " ".join(f"{k}={v}" for k, v in sweep.fixed.items())) \
        + (f" ({sweep.direction}-sweep)" if sweep.direction else "")


def outside_legend(ax, **style):
    """ax's legend to the right of it, when it has entries."""
    if ax.get_legend_handles_labels()[1]:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, **style)


def response_figure(sweep, cols):
    """One sweep's response against its x_variable; cols: sweep.csv's columns."""
    plt = pyplot()
    x_name = x_variable(sweep)
    keys = groups(cols, sweep.names, x_name)
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(9, 8), layout="constrained")
    for (label, key), (text, color) in zip(keys, group_colors(fig, axes, sweep, keys)):
        draw_response(axes, cols, x_name, select(cols, key), label=text, marker=".", ms=4, lw=1,
                      **({"color": color} if color is not None else {}))
    draw_failed(axes[0], cols, x_name)
    from_zero(axes[:2])
    axes[-1].set_xlabel(axis_label(x_name))
    if x_name in sweep.log_axes:
        axes[-1].set_xscale("log")
    outside_legend(axes[0])
    fig.suptitle(wrap(f"Response: {sweep_title(sweep)}", 90), fontsize=9)
    return fig


def bifurcation_figure(sweep, cols, poincare):
    """One sweep's Poincare indentation against its x_variable."""
    plt = pyplot()
    x_name = x_variable(sweep)
    keys = groups(cols, sweep.names, x_name)
    fig, ax = plt.subplots(figsize=(9, 5), layout="constrained")
    for (label, key), (text, color) in zip(keys, group_colors(fig, [ax], sweep, keys) if poincare else []):
        draw_bifurcation(ax, poincare, x_name, select(poincare, key), label=text,
                         **({"color": color} if color is not None else {}))
    ax.set_xlabel(axis_label(x_name))
    if x_name in sweep.log_axes:
        ax.set_xscale("log")
    outside_legend(ax, markerscale=4)
    ax.set_title(wrap(f"Bifurcation diagram (Poincare section at phase 0, after {sweep.transient:g} s): "
                      f"{sweep_title(sweep)}", 100), fontsize=9)
    return fig


DIRECTIONS = [("up", "C0", "^"), ("down", "C1", "v")]   # continuation direction, colour, marker
F_CONTACT = "f_contact: the contact resonance, linearised at the static load"


def diagrams_response_figure(runs, fc, panels, stop_time, transient):
    """The diagrams' response: one column per (amplitude, law) panel, up and down sweeps in each.
    runs: (law, amplitude label, direction) -> (sweep.csv columns, poincare columns); fc: law ->
    f_contact [Hz]; panels: [(law, law title, amplitude label, a [m])]."""
    plt = pyplot()
    fig, axes = plt.subplots(3, len(panels), figsize=(4.5 * len(panels), 9), sharex="col", squeeze=False,
                             layout="constrained")
    for j, (law, title, amp, a) in enumerate(panels):
        col = axes[:, j]
        for direction, color, marker in DIRECTIONS:
            cols, _ = runs[law, amp, direction]
            draw_response(col, cols, "f", label=f"{direction}-sweep", color=color, marker=marker, ms=3, lw=0.8)
            draw_failed(col[0], cols, "f")
        from_zero(col[:2])
        for k, ax in enumerate(col):
            ax.axvline(fc[law], color="k", lw=0.6, ls=":", label=F_CONTACT if k == 0 else "_nolegend_")
        col[0].set_title(f"{title}, a = {a * 1e6:g} $\\mu$m ($f_{{contact}}$ = {fc[law]:.1f} Hz)", fontsize=9)
        col[-1].set_xlabel("excitation frequency f [Hz]")
    fig.suptitle("Amplitude-frequency response: continuation up and down in f "
                 f"({stop_time:g} s per point, statistics after {transient:g} s)", fontsize=10)
    figure_legend(fig, axes[0], loc="outside lower center", fontsize=8)
    return fig


def diagrams_bifurcation_figure(runs, fc, panels):
    """The diagrams' bifurcation diagrams, one panel per (amplitude, law), up and down sweeps in each."""
    plt = pyplot()
    laws = list(dict.fromkeys(p[0] for p in panels))
    amps = list(dict.fromkeys(p[2] for p in panels))
    fig, axes = plt.subplots(len(amps), len(laws), figsize=(12, 4.2 * len(amps) + 0.6), squeeze=False,
                             layout="constrained")
    for law, title, amp, a in panels:
        ax = axes[amps.index(amp), laws.index(law)]
        for direction, color, marker in DIRECTIONS:
            _, pc = runs[law, amp, direction]
            draw_bifurcation(ax, pc, "f", label=f"{direction}-sweep", color=color, s=3 if direction == "up" else 2,
                             marker=marker, alpha=0.7)
        ax.axvline(fc[law], color="k", lw=0.6, ls=":", label=F_CONTACT)
        ax.set_title(f"{title}, a = {a * 1e6:g} $\\mu$m", fontsize=9)
        ax.set_xlabel("excitation frequency f [Hz]")
    fig.suptitle("Bifurcation diagrams: indentation once per excitation period (phase 0) after the transient",
                 fontsize=10)
    figure_legend(fig, axes.flat, loc="outside lower center", fontsize=8, markerscale=3)
    return fig


# ---- the benchmark (vibroimpact bench) -----------------------------------------------------------------

SOLVER_COLORS = dict(bdf="tab:blue", adams="tab:orange", dop853="tab:green", auto="tab:purple")
# a marker and line per solver: auto runs one of the others, and its curve then lies on that one's
SOLVER_STYLES = dict(bdf="o-", adams="s--", dop853="^-.", auto="x:")


def loglog_points(ax, pts, style, **kw):
    """CPU [s] against error pairs as ms against error (errors of 0 drawn at 1e-16)."""
    ax.loglog([1e3 * c for c, _ in pts], [max(e, 1e-16) for _, e in pts], style, **kw)
    no_minor_labels(ax)


def no_minor_labels(ax):
    """Log axes label their decades only (minor labels of a narrow range run into each other)."""
    from matplotlib.ticker import NullFormatter
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.yaxis.set_minor_formatter(NullFormatter())


def work_precision_figure(results, rtols, cases, solvers, bound):
    """CPU time against error per case: every solver, the Python reference, RK4. results: bench's."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(cases), figsize=(5.5 * len(cases), 5.5), squeeze=False, layout="constrained")
    axes = axes[0]
    for ax, (case, res) in zip(axes, (c for c in results.items() if c[0] in cases)):
        for name in solvers:
            pts = [(res["fmu"][name, r][0], res["fmu"][name, r][1]) for r in rtols if res["fmu"][name, r][0]]
            loglog_points(ax, pts, SOLVER_STYLES[name], color=SOLVER_COLORS[name], label=f"FMU {name}")
        pts = [res["py"][r] for r in rtols if res["py"][r][0] is not None]
        if pts:
            loglog_points(ax, pts, "s--", color="k", label="Python reference (SciPy DOP853)")
        if res["rk4"]:
            loglog_points(ax, list(res["rk4"].values()), "x:", color="tab:red", label="RK4, no event location")
        ax.axhline(bound, color="gray", lw=0.8, label=f"matched accuracy: error {bound:g}")
        ax.set_title(wrap(cases[case]["title"], 45), fontsize=10)
        ax.set_xlabel("CPU time [ms]")
        ax.set_ylabel("error" + (" (energy, restitution)" if case == "drop" else " / range of y"))
        ax.grid(True, which="both", alpha=0.3)
    figure_legend(fig, axes, ncols=4, fontsize=9)
    return fig


def cost_figure(results, solvers):
    """Cost per step against the communication step, against simulated time, against impacts."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(16, 5), layout="constrained")
    steps = sorted({h for (_, h) in results["per_step"]})
    for name in solvers:
        style = dict(color=SOLVER_COLORS[name], label=name)
        axes[0].loglog(steps, [results["per_step"][name, h] for h in steps], SOLVER_STYLES[name], **style)
        axes[1].plot(results["time_spans"], [1e3 * c for c in results["time"][name]], SOLVER_STYLES[name], **style)
        pts = results["impacts"][name]
        axes[2].plot([a for a, _ in pts], [1e3 * c for _, c in pts], SOLVER_STYLES[name], **style)
    no_minor_labels(axes[0])
    axes[0].set(xlabel="communication step [s]", ylabel="CPU time per fmi2DoStep [us]",
                title="Fig. 4b: the cost of a step against its length")
    axes[1].set(xlabel="simulated time [s]", ylabel="CPU time [ms]", title="Fig. 4b at matched rtol: against the span")
    axes[2].set(xlabel="number of impacts", ylabel="CPU time [ms]",
                title="Hertz, a = 0.1 mm, 0.1 s, rtol 1e-8: against the impacts")
    for ax in axes[1:]:
        ax.set_ylim(bottom=0)   # costs compared as ratios: a linear axis from zero
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    figure_legend(fig, axes, fontsize=9)
    return fig
