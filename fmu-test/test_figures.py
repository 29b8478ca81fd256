"""Every figure the commands make, rendered from small runs and read as a reader would: no two texts
overlap, no text leaves the figure, every axis whose values are labelled says what quantity it shows,
no legend sits on the data, and no panel is empty.

The figures come from vibroimpact.plotting, the functions the commands save (paper: each scenario and
the overview; rolling; sweep: response and bifurcation of a one-grid sweep with failed points, of
doc/sweeps.md's product sweep, of a continuation and of a sweep with more lines than a legend takes;
diagrams: response and bifurcation; bench: work-precision and cost; laws: the drops and Fig. 4b, and the
sphere between two walls of its impact_damper and clearance scenes). The
runs are the commands' own, shortened: the paper's scenarios whole (they take a fraction of a second
each), rolling and the sweeps over a few hundredths of a second and a few points, the benchmark on two
tolerances and short spans, laws without its rolling and vehicle-track scenes and one run per CPU time.

What is checked, after fig.canvas.draw():
  overlap   the window extents of the suptitle, axes titles, axis labels, visible tick labels (an
            axis' own among themselves too), offset texts, legend texts and annotations: no two
            intersect by more than OVERLAP_PX in both directions
  inside    each of them lies within the figure (to INSIDE_PX)
  labels    an axis with visible tick labels has a label that names a quantity (a word outside the
            unit's brackets, so "[um]" alone is not one)
  legends   no vertex of a line and no scatter point of any axes lies inside a legend's box
  explained a line or scatter given a label is named in a legend (else it is a mark nobody explains)
  panels    every axes is visible and draws something
  hidden    no curve the legend names lies under another: a labelled line whose every vertex is within
            HIDDEN_PX of the same vertex of another line of its axes, with the same marker and line style,
            shows only as the line on top (a colour the reader looks for and cannot find); the same for
            labelled scatter sets. Curves that are equal are one curve, labelled with every name.
  spread    an axis does not exaggerate a spread. A cost axis (its label names CPU, cost or wall time)
            on a linear scale starts at zero: costs are compared as ratios, and an axis from 0.47 to
            0.6 draws a 25 % difference as five times. Any other linear axis whose data have one sign
            and whose view leaves out zero spans at least SPREAD of its largest value: a range far
            narrower than the values' own scale draws differences of a few per cent as the full height.
            (Log axes show ratios as they are and are exempt.)
The scenario figures also say what the run did: the title's impacts and plastic loadings are the run's
(n_impacts; phases of mode 2), and every mode the run passes through is shaded where it holds.
"""
import re
import tempfile

import numpy as np
import pytest
from conftest import FMU
from matplotlib.collections import PathCollection

from vibroimpact import bench, diagrams, laws_guide, paper, plotting, rolling
from vibroimpact.reference.scenarios import SCENARIOS
from vibroimpact.sweep import engine, spec

OVERLAP_PX = 1.0   # texts may touch
INSIDE_PX = 1.0
HIDDEN_PX = 1.0    # closer than a pixel: drawn on top of each other
SPREAD = 0.1       # an axis away from zero spans at least this fraction of its largest value
COST = re.compile(r"\bCPU\b|\bcost\b|\bwall\b", re.IGNORECASE)
RUN_TIMEOUT_S = 120


# ---- the checks ------------------------------------------------------------------------------------------

def visible_ticks(axis):
    """The tick label texts the axis draws (the ticks inside its view)."""
    out = []
    for tick in axis._update_ticks():
        out += [t for t, on in ((tick.label1, tick.label1.get_visible()), (tick.label2, tick.label2.get_visible()))
                if on]
    return out


def texts(fig):
    """[(what, Text)] of every visible, non-empty text of the figure."""
    found = [("suptitle", fig._suptitle)] if fig._suptitle is not None else []
    found += [("figure text", t) for t in fig.texts if t is not fig._suptitle]
    for leg in fig.legends:
        found += [("figure legend", t) for t in leg.get_texts()]
    for i, ax in enumerate(fig.axes):
        name = f"axes {i} '{ax.get_title() or ax.get_ylabel()}'"[:70]
        found += [(f"{name} title", t) for t in (ax.title, ax._left_title, ax._right_title)]
        found += [(f"{name} x label", ax.xaxis.label), (f"{name} y label", ax.yaxis.label)]
        found += [(f"{name} x offset", ax.xaxis.offsetText), (f"{name} y offset", ax.yaxis.offsetText)]
        found += [(f"{name} x tick", t) for t in visible_ticks(ax.xaxis)]
        found += [(f"{name} y tick", t) for t in visible_ticks(ax.yaxis)]
        found += [(f"{name} text", t) for t in ax.texts]
        if ax.get_legend() is not None:
            found += [(f"{name} legend", t) for t in ax.get_legend().get_texts()]
    return [(w, t) for w, t in found if t.get_visible() and t.get_text().strip() and ax_visible(t)]


def ax_visible(text):
    ax = text.axes
    return ax is None or (ax.get_visible() and ax.axison) or text is ax.title


def overlaps(a, b, tol=OVERLAP_PX):
    return (min(a.x1, b.x1) - max(a.x0, b.x0) > tol) and (min(a.y1, b.y1) - max(a.y0, b.y0) > tol)


def text_problems(fig, renderer):
    found = [(w, t, t.get_window_extent(renderer)) for w, t in texts(fig)]
    box = fig.bbox
    problems = []
    for w, t, b in found:
        if b.x0 < box.x0 - INSIDE_PX or b.y0 < box.y0 - INSIDE_PX or b.x1 > box.x1 + INSIDE_PX \
                or b.y1 > box.y1 + INSIDE_PX:
            problems.append(f"{w} {t.get_text()!r} leaves the figure")
    for i in range(len(found)):
        for j in range(i + 1, len(found)):
            (w1, t1, b1), (w2, t2, b2) = found[i], found[j]
            if overlaps(b1, b2):
                problems.append(f"{w1} {t1.get_text()!r} overlaps {w2} {t2.get_text()!r}")
    return problems


def names_a_quantity(label):
    """A word outside the unit's brackets: "contact force F [kN]" does, "[um]" does not."""
    return re.search(r"[A-Za-z]{2,}", re.sub(r"\[[^\]]*\]", "", label)) is not None


def label_problems(fig):
    problems = []
    for i, ax in enumerate(fig.axes):
        if not (ax.get_visible() and ax.axison):
            continue
        for axis, which in ((ax.xaxis, "x"), (ax.yaxis, "y")):
            if not [t for t in visible_ticks(axis) if t.get_text().strip()]:
                continue
            label = axis.label.get_text() if axis.label.get_visible() else ""
            if not names_a_quantity(label):
                problems.append(f"axes {i} '{ax.get_title()[:50]}': the {which} axis shows values under the "
                                f"label {label!r}, which names no quantity")
    return problems


def data_points(ax):
    """Display coordinates of every line vertex and scatter point of the axes."""
    pts = [line.get_transform().transform(line.get_xydata()) for line in ax.lines if line.get_visible()]
    pts += [c.get_offset_transform().transform(c.get_offsets()) for c in ax.collections
            if c.get_visible() and len(c.get_offsets())]
    pts = [p for p in pts if len(p)]
    return np.concatenate(pts) if pts else np.empty((0, 2))


def legend_problems(fig):
    legends = [(f"legend of axes {i}", ax.get_legend()) for i, ax in enumerate(fig.axes)
               if ax.get_legend() is not None] + [("figure legend", leg) for leg in fig.legends]
    problems = []
    for what, leg in legends:
        b = leg.get_window_extent()
        for i, ax in enumerate(fig.axes):
            p = data_points(ax)
            p = p[np.all(np.isfinite(p), axis=1)]
            inside = (p[:, 0] > b.x0 + 1) & (p[:, 0] < b.x1 - 1) & (p[:, 1] > b.y0 + 1) & (p[:, 1] < b.y1 - 1)
            if inside.any():
                problems.append(f"{what} covers {int(inside.sum())} data points of axes {i} '{ax.get_title()[:50]}'")
    return problems


def explained_problems(fig):
    named = {t.get_text() for ax in fig.axes if ax.get_legend() is not None for t in ax.get_legend().get_texts()}
    named |= {t.get_text() for leg in fig.legends for t in leg.get_texts()}
    problems = []
    for i, ax in enumerate(fig.axes):
        for artist in list(ax.lines) + list(ax.collections):
            label = artist.get_label()
            if artist.get_visible() and label and not label.startswith("_") and label not in named:
                problems.append(f"axes {i} '{ax.get_title()[:50]}': {label!r} is drawn but no legend names it")
    return problems


def panel_problems(fig):
    problems = []
    for i, ax in enumerate(fig.axes):
        if not (ax.get_visible() and ax.axison):
            problems.append(f"axes {i} is an empty panel (turned off)")
        elif not (ax.lines or ax.collections or ax.images or ax.patches):
            problems.append(f"axes {i} '{ax.get_title()[:50]}' draws nothing")
    return problems


def labelled(artists):
    return [a for a in artists if a.get_visible() and a.get_label() and not a.get_label().startswith("_")]


def covered(a, b):
    """True when every point of a (n x 2 display coordinates) is within HIDDEN_PX of the same point of b."""
    return a.shape == b.shape and len(a) > 0 and bool(np.all(np.hypot(*(a - b).T) <= HIDDEN_PX))


def hidden_problems(fig):
    problems = []
    for i, ax in enumerate(fig.axes):
        lines = [(ln, ln.get_transform().transform(ln.get_xydata()), (ln.get_marker(), ln.get_linestyle()))
                 for ln in labelled(ax.lines)]
        sets = [(c, c.get_offset_transform().transform(c.get_offsets()),
                 (tuple(p.vertices.round(6).tobytes() for p in c.get_paths()), tuple(c.get_sizes())))
                for c in labelled(ax.collections) if isinstance(c, PathCollection)]
        for group in (lines, sets):
            for k, (a, pa, sa) in enumerate(group):
                for b, pb, sb in group[k + 1:]:
                    if sa == sb and covered(pa, pb):
                        problems.append(f"axes {i} '{ax.get_title()[:50]}': {a.get_label()!r} lies hidden under "
                                        f"{b.get_label()!r} (same points, same style)")
    return problems


def spread_problems(fig):
    problems = []
    for i, ax in enumerate(fig.axes):
        if not (ax.get_visible() and ax.axison):
            continue
        data = ax.dataLim
        for which, scale, (lo, hi), (d0, d1), label in (
                ("x", ax.get_xscale(), sorted(ax.get_xlim()), (data.x0, data.x1), ax.get_xlabel()),
                ("y", ax.get_yscale(), sorted(ax.get_ylim()), (data.y0, data.y1), ax.get_ylabel())):
            if scale != "linear" or not (np.isfinite(d0) and np.isfinite(d1)):
                continue
            where = f"axes {i} '{ax.get_title()[:50]}': the {which} axis {label!r}"
            if COST.search(label) and lo > 0:
                problems.append(f"{where} is a cost axis from {lo:.3g}, not from zero")
            elif (d0 >= 0 and lo > 0 or d1 <= 0 and hi < 0) and hi - lo < SPREAD * max(abs(lo), abs(hi)):
                problems.append(f"{where} spans {lo:.3g} to {hi:.3g}: less than {SPREAD:g} of its values' scale")
    return problems


def problems(fig):
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    return (text_problems(fig, renderer) + label_problems(fig) + legend_problems(fig) + explained_problems(fig)
            + panel_problems(fig) + hidden_problems(fig) + spread_problems(fig))


def check(fig):
    try:
        found = problems(fig)
    finally:
        plotting.pyplot().close(fig)
    assert not found, f"{len(found)} problems:\n  " + "\n  ".join(found[:40])


# ---- the small runs --------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def paper_runs():
    runs = {}
    for name, scenario in SCENARIOS.items():
        r = paper.simulate(scenario, FMU)
        runs[name] = (scenario, r, paper.summarize(name, r))
    return runs


@pytest.fixture(scope="module")
def interface():
    return spec.Interface(str(FMU))


def small_sweep(interface, sets, grids, stop_time=0.02, transient=0.01, direction=None, log=()):
    """A sweep as `vibroimpact sweep --set ... --grid ...` makes it, run here, its files read back."""
    sweep = spec.Sweep(fixed=dict(spec.parse_set(interface, s) for s in sets),
                       grids=[spec.parse_grid(interface, g, g.split("=")[0] in log) for g in grids],
                       stop_time=stop_time, step=1e-5, transient=transient, direction=direction, log_axes=tuple(log),
                       title=" ".join(sets))
    rows = engine.run_here(sweep, interface, str(FMU))
    with tempfile.TemporaryDirectory() as tmp:
        engine.write(tmp, sweep, rows)
        cols, poincare = engine.read(tmp)
    return sweep, cols, poincare


SWEEPS = {
    # one grid, with points the FMU refuses (nu1 >= 0.5)
    "failed points": (["contact_model=hertz", "a=1e-4"], ["nu1=0.1:0.7:4"], {}),
    # doc/sweeps.md's product sweep, on a shorter f grid
    "product": (["contact_model=johnson", "Y=6e8"], ["a=1e-6:1e-4:2", "f=200:400:21"], dict(log=("a",))),
    "continuation": (["contact_model=hertz", "a=5e-6"], ["f=200:330:6"], dict(direction="up")),
    # more lines than a legend takes: one colour scale
    "many lines": (["contact_model=hertz"], ["a=1e-5:1e-4:11", "f=200:400:12"], dict(stop_time=0.01, transient=0.0)),
}


@pytest.fixture(scope="module")
def sweeps(interface):
    return {name: small_sweep(interface, sets, grids, **kw) for name, (sets, grids, kw) in SWEEPS.items()}


@pytest.fixture(scope="module")
def diagram_runs(interface):
    runs = {}
    for amp, a, _, _ in diagrams.AMPLITUDES:
        for law, _, law_sets in diagrams.LAWS:
            for direction in diagrams.DIRECTIONS:
                sw = diagrams.sweep_of(interface, diagrams.PAPER + law_sets + [f"a={a}"], "f=200:330:4", direction,
                                       True, stop_time=0.02, transient=0.01)
                rows = engine.run_here(sw, interface, str(FMU))
                with tempfile.TemporaryDirectory() as tmp:
                    engine.write(tmp, sw, rows)
                    runs[law, amp, direction] = engine.read(tmp)
    fc = {law: diagrams.f_contact(str(FMU), interface, diagrams.PAPER + sets) for law, _, sets in diagrams.LAWS}
    return runs, fc


@pytest.fixture(scope="module")
def bench_results(tmp_path_factory):
    build = FMU.parent
    missing = [p for p in bench.PROGRAMS if not (build / p).is_file()]
    if missing:
        pytest.fail(f"{missing} missing in {build}: build them (cmake --build build)")
    work = tmp_path_factory.mktemp("bench")
    fmu = bench.Fmu(work, build)
    rtols = [1e-4, 1e-7]
    results = {case: bench.measure_case(fmu, work, case, {**c, "t_stop": min(c["t_stop"], 0.005)}, rtols, 1,
                                        rk4_steps=bench.RK4_STEPS[:3])
               for case, c in bench.CASES.items()}
    results["fig4b"]["matched"] = {}
    bench.per_step_cost(lambda *_: None, fmu, results, 1, steps=[1e-6, 1e-5, 1e-4], t_stop=0.002)
    bench.scaling(lambda *_: None, fmu, results, 1, spans=[0.002, 0.005], freqs=[500.0, 1000.0])
    return results, rtols


@pytest.fixture(scope="module")
def laws_rows(tmp_path_factory):
    """The laws command's rows of the drops and of Fig. 4b (its figure's first two panels)."""
    scenes = [s for s in laws_guide.SCENES if s.startswith("drop") or s == "fig4b"]
    return laws_guide.run(tmp_path_factory.mktemp("laws"), FMU, only_scenes=scenes, repeat=1)


# ---- the figures -----------------------------------------------------------------------------------------

@pytest.mark.timeout(RUN_TIMEOUT_S)
@pytest.mark.parametrize("name", list(SCENARIOS))
def test_a_scenario_figure_reads_well(paper_runs, name):
    check(plotting.scenario_figure(*paper_runs[name]))


@pytest.mark.timeout(RUN_TIMEOUT_S)
@pytest.mark.parametrize("name", list(SCENARIOS))
def test_a_scenario_figure_says_what_the_run_did(paper_runs, name):
    """The title's counts are the run's: 'N impacts' the final n_impacts (contact onsets), 'M plastic
    loadings' the phases of mode 2 counted here; every mode of the run is shaded by an artist named
    'mode K: ...' whose spans hold every sample in that mode (and none of another)."""
    scenario, r, s = paper_runs[name]
    fig = plotting.scenario_figure(scenario, r, s)
    try:
        fig.canvas.draw()
        title = fig._suptitle.get_text().replace("\n", " ")
        mode = np.asarray(r["mode"]).astype(int)
        plastic = int(mode[0] == 2) + int(np.count_nonzero((mode[1:] == 2) & (mode[:-1] != 2)))
        assert f"{int(r['n_impacts'][-1])} impacts" in title, title
        assert f"{plastic} plastic loadings" in title, title
        ax = fig.axes[0]
        shaded = {c.get_label().split(":")[0]: c for c in ax.collections if c.get_label().startswith("mode ")}
        assert sorted(shaded) == [f"mode {k}" for k in sorted(set(mode))], (sorted(shaded), sorted(set(mode)))
        t = 1e3 * np.asarray(r["time"][:-1])
        for k in set(mode):
            spans = [(p.vertices[:, 0].min(), p.vertices[:, 0].max()) for p in shaded[f"mode {k}"].get_paths()]
            inside = np.zeros(len(t), bool)
            for a, b in spans:
                inside |= (t >= a) & (t < b)
            assert np.array_equal(inside, mode[:-1] == k), (k, int(np.sum(inside != (mode[:-1] == k))))
    finally:
        plotting.pyplot().close(fig)


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_laws_figure_reads_well(laws_rows):
    check(laws_guide.figure(laws_rows))


@pytest.fixture(scope="module")
def laws_wall_rows(tmp_path_factory):
    """The laws command's rows of its two-wall scenes with the variants its wall figure draws."""
    return laws_guide.run(tmp_path_factory.mktemp("laws_walls"), FMU, only_scenes=list(laws_guide.WALL_SCENES),
                          variants=list(laws_guide.TRACE_VARIANTS), repeat=1)


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_laws_wall_figure_reads_well(laws_wall_rows):
    check(laws_guide.walls_figure(laws_wall_rows))


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_laws_wall_figure_marks_every_impact(laws_wall_rows):
    """Each variant's impacts in the last cycles are marked on its curve, on the wall they hit: as many
    markers of each kind as contact onsets its trace counts, each where the sphere touches that wall (y
    within 0.1 mm of yC, or of yC + gap)."""
    fig = laws_guide.walls_figure(laws_wall_rows)
    try:
        fig.canvas.draw()
        f = laws_guide.SHAKEN["f"]
        for ax, scene in zip(fig.axes, laws_guide.WALL_SCENES):
            marks = {c.get_label(): c.get_offsets() for c in ax.collections if isinstance(c, PathCollection)}
            for r in (r for r in laws_wall_rows if r["scene"] == scene):
                tr = r["trace"]
                for key, wall, offset in (("n_impacts", "lower", 0.0), ("n_impacts_upper", "upper", tr["gap"])):
                    xy = np.asarray(marks[f"impact on the {wall} wall, {r['variant']}"])
                    assert len(xy) == int(tr[key][-1] - tr[key][0]) > 0, (scene, r["variant"], wall)
                    wall_mm = 1e3 * (np.interp(xy[:, 0] / f, tr["time"], tr["yC"]) + offset)
                    assert np.all(np.abs(xy[:, 1] - wall_mm) < 0.1), (scene, r["variant"], wall)
    finally:
        plotting.pyplot().close(fig)


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_overview_reads_well(paper_runs):
    check(plotting.overview_figure({n: (s, r) for n, (s, r, _) in paper_runs.items()}))


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_rolling_figure_reads_well(tmp_path):
    x, h = rolling.corrugation(tmp_path / "corrugation.txt")
    runs = rolling.run(tmp_path / "corrugation.txt", FMU, stop_time=0.02)
    check(plotting.rolling_figure((*rolling.constraint(x, h), rolling.R1), runs, rolling.PASSING))


@pytest.mark.timeout(RUN_TIMEOUT_S)
@pytest.mark.parametrize("name", list(SWEEPS))
def test_a_sweep_response_reads_well(sweeps, name):
    sweep, cols, _ = sweeps[name]
    if name == "failed points":
        assert any(s != "ok" for s in cols["status"]), "the sweep meant to have failed points has none"
    check(plotting.response_figure(sweep, cols))


@pytest.mark.timeout(RUN_TIMEOUT_S)
@pytest.mark.parametrize("name", list(SWEEPS))
def test_a_bifurcation_diagram_reads_well(sweeps, name):
    sweep, cols, poincare = sweeps[name]
    check(plotting.bifurcation_figure(sweep, cols, poincare))


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_diagrams_response_reads_well(diagram_runs):
    runs, fc = diagram_runs
    check(plotting.diagrams_response_figure(runs, fc, diagrams.panels(), 0.02, 0.01))


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_diagrams_bifurcation_reads_well(diagram_runs):
    runs, fc = diagram_runs
    check(plotting.diagrams_bifurcation_figure(runs, fc, diagrams.panels()))


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_work_precision_plot_reads_well(bench_results):
    results, rtols = bench_results
    check(plotting.work_precision_figure(results, rtols, bench.CASES, bench.SOLVERS, bench.BOUND))


@pytest.mark.timeout(RUN_TIMEOUT_S)
def test_the_cost_plot_reads_well(bench_results):
    results, _ = bench_results
    check(plotting.cost_figure(results, bench.SOLVERS))


# ---- the checks themselves can fail ----------------------------------------------------------------------

def test_the_checks_see_hidden_curves_cost_axes_off_zero_and_narrow_spreads():
    plt = plotting.pyplot()
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(12, 3), layout="constrained")
    x = np.array([0.1, 1.0, 3.0])
    a.plot(x, [1.0, 1.0, 1.0], "o-", label="under")
    a.plot(x, [1.0, 1.0, 1.0 + 1e-6], "o-", label="over")
    a.plot(x, [0.5, 0.5, 0.5], "o-", label="alike")
    a.plot(x, [0.5, 0.5, 0.5], "s--", label="styled apart")
    a.scatter([1.0], [0.2], label="point under")
    a.scatter([1.0], [0.2], label="point over")
    a.legend(loc="upper left", bbox_to_anchor=(1, 1))
    a.set(xlabel="speed [m/s]", ylabel="restitution")
    b.scatter([0.47, 0.6], [1.0, 4.0])
    b.set(xlabel="CPU per simulated second [s/s]", ylabel="peak force / hertz's")
    c.plot([0, 1], [100.0, 101.0])
    c.set(xlabel="time [s]", ylabel="temperature [K]")
    found = problems(fig)
    plt.close(fig)
    text = "\n".join(found)
    assert "'under' lies hidden under 'over'" in text and "'point under' lies hidden under 'point over'" in text
    assert "'alike'" not in text, text   # a marker and a line style apart: both seen
    assert "'CPU per simulated second [s/s]' is a cost axis from" in text, text
    assert "'temperature [K]' spans" in text, text
    assert "peak force" not in text and "'speed [m/s]'" not in text, text


def test_the_checks_see_overlaps_bare_units_covering_legends_unexplained_marks_and_empty_panels():
    plt = plotting.pyplot()
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(6, 3))
    a.plot(np.linspace(0, 1, 51), np.linspace(0, 1, 51), label="a line")
    a.legend(loc="center")
    a.set_ylabel("[um]")
    a.set_title("a title much too long for its panel")
    b.set_title("running into the next one")
    b.plot([0, 1], [1, 0], "x", label="failed")
    b.set(xlabel="time [s]", ylabel="force [N]")
    c.set_title("a title that runs off the right edge of the figure")
    c.axis("off")
    found = "\n".join(problems(fig))
    plt.close(fig)
    for words in ("overlaps", "names no quantity", "covers", "'failed' is drawn but no legend names it",
                  "empty panel", "leaves the figure"):
        assert words in found, (words, found)
