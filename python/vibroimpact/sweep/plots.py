"""Figures from the sweep's CSV files: the response against the first grid variable (maximum and
minimum force, largest separation, contact fraction) and the bifurcation diagram (the Poincare
indentation). sweep_figures draws one sweep; the draw_* functions are what vibroimpact.diagrams
combines into the up/down, Hertz/Johnson figures."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import engine  # noqa: E402

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


def sweep_figures(out_dir, sweep, rows=None):
    """DIR/response.png and DIR/bifurcation.png for one sweep (read back from its CSV files)."""
    if not sweep.grids:
        return []
    cols, poincare = engine.read(out_dir)
    x_name = sweep.names[0]
    logx = x_name in sweep.log_axes
    title = (sweep.title or " ".join(f"{k}={v}" for k, v in sweep.fixed.items())) \
        + (f" ({sweep.direction}-sweep)" if sweep.direction else "")
    keys = groups(cols, sweep.names)
    legend = 1 < len(keys) <= MAX_LINES

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 8))
    for label, key in keys:
        draw_response(axes, cols, x_name, select(cols, key), label=label, marker=".", ms=4, lw=1)
    axes[-1].set_xlabel(axis_label(x_name))
    if logx:
        axes[-1].set_xscale("log")
    if legend:
        axes[0].legend(fontsize=7)
    axes[0].set_title(f"Response: {title}", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "response.png"), dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 5))
    for label, key in keys if poincare else []:
        draw_bifurcation(ax, poincare, x_name, select(poincare, key), label=label)
    ax.set_xlabel(axis_label(x_name))
    if logx:
        ax.set_xscale("log")
    if legend:
        ax.legend(fontsize=7, markerscale=4)
    ax.set_title(f"Bifurcation diagram (Poincare section at phase 0, after {sweep.transient:g} s): {title}",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "bifurcation.png"), dpi=110)
    plt.close(fig)
    return [os.path.join(out_dir, "response.png"), os.path.join(out_dir, "bifurcation.png")]
