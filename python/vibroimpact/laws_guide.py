"""What each contact law and option changes in a scene, and what it costs (doc/choosing.md).

The same scenes run with each law and each option that can be switched off, through the FMU:
    drop_<V>   a steel sphere (R = 10 mm, 32.88 g) dropped at V = 0.1, 1, 3 m/s on a steel plane, no load
    fig4b      the paper's harmonic excitation (a = 0.1 mm, f = 560 Hz, the paper's wheel, Y = 600 MPa)
    rolling    the paper's wheel rolling over a corrugated rail (lambda = 50 mm, 0.1 mm) near resonance
    vehicle_track  the vehicle-track example (vibroimpact.vehicle_track): the contact FMU as the wheel-rail
               contact between a vehicle FMU and a track FMU, 30 m/s over a rough rail (ISO 3095 + 15 dB),
               in the example's recommended co-simulation and its Model Exchange master
    impact_damper  the sphere in a cavity 10 mm high (the upper stop: upper_stop, gap) shaken
               a (cos(2 pi f t) - 1) at a = 1 mm, 50 Hz, without gravity, thrown up from the floor at
               1.5 m/s; 0.4 s, the second half settled (the closed form: cavity_orbit)
    clearance  the sphere in a clearance of 0.5 mm under gravity on the same platform, from rest on the
               lower flank: it rattles between the flanks (backlash); 0.4 s
and each run gives what it changes (peak force, restitution, dissipated work, response amplitude, event
count) and what it costs (CPU per simulated second in Co-Simulation and Model Exchange, events per
simulated second); in the vehicle-track scene also how far its co-simulation is from its Model Exchange
master at small steps (vt_agreement). The variants: hertz (elastic), johnson (plasticity, fixed contact
point, the paper's unloading with stick), johnson_continuous (no stick), johnson_moving (moving contact
point), lepp, thornton, hertz_damped (exact damping, e = 0.6), hunt_crossley (e = 0.6), linear (e = 0.6).
The two-wall scenes (impact_damper, clearance) also give, over their settled second half, what each wall
sees: the speed the sphere leaves a wall with, the impacts per cycle and the peak force on each wall, and
the energy dissipated per cycle (walls()); and a trace of the last cycles for their figure
(walls_figure).
"""
import math
import pathlib
import time

import numpy as np

from . import rolling
from .files import replacing
from .fmu import Logged, MessageLog, fmu_path
from .vehicle_track import master as vt_master
from .vehicle_track import me_master as vt_me
from .vehicle_track import parameters as vt_parameters
from .vehicle_track import roughness

E_DAMPED = 0.6  # the damped variants' e_restitution
VARIANTS = {
    "hertz": dict(contact_model=1),
    "johnson": dict(contact_model=2),
    "johnson_continuous": dict(contact_model=2, unloading=2),
    "johnson_moving": dict(contact_model=2, moving_contact=True),
    "lepp": dict(contact_model=3),
    "thornton": dict(contact_model=6),
    "hertz_damped": dict(contact_model=4, damping_formula=1, e_restitution=E_DAMPED),
    "hunt_crossley": dict(contact_model=4, damping_formula=2, e_restitution=E_DAMPED),
    "linear": dict(contact_model=5, e_restitution=E_DAMPED),
}
# the steel sphere of Johnson's Hertz case on a steel plane (the FMU's E, nu), Y = 1 GPa
SPHERE = dict(R1=0.01, R2=0.0, m=0.03288, Y=1e9, P=0.0, g=0.0, init=2)
DROP_SPEEDS = (0.1, 1.0, 3.0)  # m/s
WALL_SCENES = ("impact_damper", "clearance")   # the sphere between two walls (the upper stop)
# scenes()' names
SCENES = tuple(f"drop_{V:g}" for V in DROP_SPEEDS) + ("fig4b", "rolling", "vehicle_track") + WALL_SCENES
PAPER = dict(Y=6e8, a=1e-4, f=560.0)
STOP = {"drop": 2e-3, "fig4b": 0.05, "rolling": 0.05, "vehicle_track": 0.03, "walls": 0.4}  # s
# the two-wall scenes: the sphere on a platform shaken a (cos(2 pi f t) - 1), a second surface gap above
# the floor moving with it; the impact damper without gravity, thrown up at v0; the clearance under gravity
SHAKEN = dict(a=1e-3, f=50.0, upper_stop=True)   # m, Hz
WALLS = {"impact_damper": dict(gap=0.01, v0=1.5), "clearance": dict(gap=5e-4, g=9.81)}   # m, m/s, m/s2
TRACE_CYCLES = 3   # the last cycles the figure of the two-wall scenes draws
# the vehicle-track run starts where the roughness fades in (roughness.taper), 0.9 m before its end
VT_X0 = 1.0  # m
INTERVAL = 1e-6  # s, output interval of the drops (contact times of tens of us)
RTOL = 1e-8
# the communication (Co-Simulation) and output (Model Exchange) interval of the timed runs [s]; fmpy's
# CVode takes at most 500 steps per output interval
TIMED_INTERVAL = 1e-5
COLUMNS = ["scene", "variant", "F_max_N", "restitution", "W_dissipated_J", "y_pp_um", "events", "cpu_cs_s_per_s",
           "cpu_me_s_per_s", "events_per_s"]
# the vehicle-track scene's co-simulation steps compared with its Model Exchange master [s], and the
# intervals its mean force is compared over [s]
AGREEMENT_STEPS = (2e-6, 1e-6)
AGREEMENT_MEAN = 1e-5


def hertz_constant(R, E=2.1e11, nu=0.3):
    """K = 4/3 E* sqrt(R*) of two equal materials on a plane."""
    return 4 / 3 * E / (2 * (1 - nu * nu)) * math.sqrt(R)


def k_spring_for(scene):
    """The linear variant's spring: the Hertz secant stiffness F_max/delta_max of the sphere's 1 m/s impact for
    the drops and the two-wall scenes (the closed form, delta_max = (5 m V^2/(4 K))^(2/5)); the FMU's default
    (about the Hertz tangent stiffness of the paper's static load) for the paper's wheel."""
    if not (scene.startswith("drop") or scene in WALL_SCENES):
        return 1.2e9
    K = hertz_constant(SPHERE["R1"])
    d = (1.25 * SPHERE["m"] / K) ** 0.4
    return K * math.sqrt(d)


def scenes(profile, rough=None):
    """scene -> (FMU parameters, stop time [s], impact speed [m/s] or None); profile: the corrugation file;
    rough: the vehicle-track example's roughness file (None: no vehicle-track scene)."""
    out = {f"drop_{V:g}": (dict(SPHERE, v0=-V), STOP["drop"], V) for V in DROP_SPEEDS}
    out["fig4b"] = (dict(PAPER), STOP["fig4b"], None)
    out["rolling"] = (dict(contact_model=1, profile_file=str(profile), V=rolling.PASSING["near"] * rolling.LAMBDA,
                           profile_periodic=True, Y=6e8), STOP["rolling"], None)
    if rough is not None:
        out["vehicle_track"] = (dict(profile_file=str(rough), x0=VT_X0), STOP["vehicle_track"], None)
    for scene in WALL_SCENES:
        out[scene] = (dict(SPHERE, **SHAKEN, **WALLS[scene]), STOP["walls"], None)
    return out


def cavity_orbit(e, a, f, gap):
    """The closed form of the impact damper: (phi, u) of the periodic motion a sphere in a cavity shaken
    a (cos(2 pi f t) - 1), without gravity or load, with instantaneous impacts of restitution e, settles
    into: two impacts per cycle, one on each wall, half a period apart, each at the free-flight speed
    u = (1+e)/(1-e) a w cos(phi) [m/s], the phase phi in (-pi/2, 0) solving
    gap = 2 a sin(phi) + (1+e)/(1-e) a pi cos(phi) (the stable one of its two solutions). Each impact
    takes 1/2 m (1 - e^2) (2u/(1+e))^2 in the wall's frame: 4 m u^2 (1-e)/(1+e) per cycle."""
    from scipy.optimize import brentq
    w, r = 2 * math.pi * f, (1 + e) / (1 - e)
    phi = brentq(lambda p: 2 * a * math.sin(p) + r * a * math.pi * math.cos(p) - gap, -math.pi / 2, 0.0, xtol=1e-15)
    return phi, r * a * w * math.cos(phi)


WALL_OUTPUTS = ["yC", "F_upper", "mode", "mode_upper", "n_impacts", "n_impacts_upper", "W_dissipated"]


def _events(fmu, md, unzipdir, params, stop):
    """The result of one Co-Simulation run with its event log on, and its log (a fmu.MessageLog); with
    the upper stop also both walls' outputs (WALL_OUTPUTS)."""
    from fmpy import simulate_fmu
    log = Logged(md, unzipdir, name="events")
    slave = log.instantiate(logging=True)
    slave.setDebugLogging(True, ["logEvents"])
    try:
        r = simulate_fmu(fmu, fmu_instance=slave, model_description=md, start_values=params, stop_time=stop,
                         output_interval=INTERVAL if stop <= STOP["drop"] else 1e-5, relative_tolerance=RTOL,
                         output=["v", "y", "F", "W_plastic", "contact"]
                         + (WALL_OUTPUTS if params.get("upper_stop") else []))
    finally:
        slave.freeInstance()
    return r, log


def _count_events(log):
    """The number of events an instance's event log (logEvents) holds, the start once (with the upper
    stop the start has a line per contact)."""
    return sum(1 for _, _, m in log.messages
               if m.startswith("event t=") and not ("kind=start" in m and "contact=upper" in m))


def _cpu(run, repeat):
    """The smallest process time of `repeat` calls of run() [s]; NaN when the run fails (its reason is
    printed: an importer's integrator that gives up is a result of the table too)."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.process_time()
        try:
            run()
        except Exception as e:  # noqa: BLE001 (any failure of the importer or the FMU)
            print(f"  failed: {str(e).splitlines()[0][:160]}")
            return math.nan
        best = min(best, time.process_time() - t0)
    return best


def _cs_run(fmu_dir, md, params, stop):
    """One Co-Simulation run of the extracted FMU without logging, for its CPU time."""
    from fmpy import simulate_fmu
    slave = Logged(md, fmu_dir, name="cpu").instantiate()
    try:
        simulate_fmu(fmu_dir, fmu_instance=slave, model_description=md, start_values=params, stop_time=stop,
                     relative_tolerance=RTOL, output=["y"], output_interval=TIMED_INTERVAL)
    finally:
        slave.freeInstance()


def _me_run(fmu, fmu_dir, md, params, stop):
    from .me import run_me
    run_me(fmu, params, stop, rtol=RTOL, output=("y",), output_interval=TIMED_INTERVAL, unzipdir=fmu_dir, md=md)


def _vt_cs(fmu, params, stop, step=TIMED_INTERVAL, **options):
    """The vehicle-track example's recommended co-simulation (Gauss-Seidel vehicle, contact, track; the rail
    extrapolated with its velocity, in vC_in; F_mean to the track) with the contact FMU's start values
    `params` (the law and the roughness file), communication step `step` [s]; the companion FMUs beside
    `fmu`."""
    build = pathlib.Path(fmu).parent
    vt_parameters.companion_fmus(build)
    profile = params["profile_file"]
    contact = {k: v for k, v in params.items() if k != "profile_file"}
    return vt_master.run(step, stop, "gauss-seidel", ("vehicle", "contact", "track"), "F_mean", "ramp",
                         profile, build=build, rtol=RTOL, contact=contact, **options)


def _vt_events(fmu, params, stop):
    """One co-simulation of the vehicle-track example with the contact FMU's event log on: its record in
    the names of a contact FMU's result (time, F, y, W_plastic) and the contact FMU's log."""
    log = MessageLog()
    rec = _vt_cs(fmu, params, stop, contact_log=log, record=("W_plastic",))
    r = {"time": rec["t"], "F": rec["contact.F"], "y": rec["contact.y"], "W_plastic": rec["contact.W_plastic"]}
    return r, log


def _vt_cs_run(fmu, params, stop):
    """The timed co-simulation: the contact FMU's log kept, not printed (_vt_events relays its warnings),
    and no event log."""
    _vt_cs(fmu, params, stop, contact_log=MessageLog(limit=0), contact_events=False)


def _vt_me_run(fmu, params, stop):
    """The vehicle-track example's three FMUs as Model Exchange in one solver (DOP853, the table's rtol)."""
    build = pathlib.Path(fmu).parent
    contact = {k: v for k, v in params.items() if k != "profile_file"}
    vt_me.run(stop, params["profile_file"], rtol=RTOL, build=build, dt_out=TIMED_INTERVAL, contact=contact)


def vt_agreement(fmu, params, stop):
    """The vehicle-track scene's Model Exchange master (the table's rtol) against its co-simulation at each
    step of AGREEMENT_STEPS: {'me_vs_cs_<step>': max over intervals of AGREEMENT_MEAN of |mean force,
    co-simulation - Model Exchange| / W}, W the static wheel load (the force at the static start). Both
    mean forces are impulses over the interval, so a force that jumps (Johnson's paper unloading at a
    turning point) weighs by how long it lasts, not by where a grid point falls."""
    build = pathlib.Path(fmu).parent
    contact = {k: v for k, v in params.items() if k != "profile_file"}
    me = vt_me.run(stop, params["profile_file"], rtol=RTOL, build=build, dt_out=AGREEMENT_MEAN, contact=contact)
    me_mean = np.diff(me["J"]) / AGREEMENT_MEAN
    W = float(me["contact.F"][0])
    out = {}
    for h in AGREEMENT_STEPS:
        k = int(round(AGREEMENT_MEAN / h))
        cs_mean = _vt_cs(fmu, params, stop, step=h, contact_log=MessageLog(limit=0),
                         contact_events=False)["contact.F_mean"][1:].reshape(-1, k).mean(axis=1)
        out[f"me_vs_cs_{h:g}"] = float(np.max(np.abs(cs_mean - me_mean))) / W
    return out


def measure(scene, variant, params, stop, V, fmu, md, unzipdir, repeat=1, warned=None):
    """One table row: what the variant gives in the scene and what it costs. warned: called with
    ('SCENE VARIANT', the FMU's warnings) when the FMU logged any in the run measured (a fmu.Relay)."""
    print(f"{scene}: {variant}")
    p = dict(params, **VARIANTS[variant])
    if variant == "linear":
        p["k_spring"] = k_spring_for(scene)
    if scene == "vehicle_track":
        r, log = _vt_events(fmu, p, stop)
        cs = _cpu(lambda: _vt_cs_run(fmu, p, stop), repeat)
        me = _cpu(lambda: _vt_me_run(fmu, p, stop), repeat)
        agreement = {} if math.isnan(me) else vt_agreement(fmu, p, stop)  # NaN: the master failed (printed)
    else:
        agreement = {}
        r, log = _events(fmu, md, unzipdir, p, stop)
        cs = _cpu(lambda: _cs_run(unzipdir, md, p, stop), repeat)
        me = _cpu(lambda: _me_run(fmu, unzipdir, md, p, stop), repeat)
    if warned is not None and log.warnings():
        warned(f"{scene} {variant}", log.warnings())
    events = _count_events(log)
    half = r["time"] >= stop / 2
    row = dict(scene=scene, variant=variant, F_max_N=float(r["F"].max()), events=events,
               cpu_cs_s_per_s=cs / stop, cpu_me_s_per_s=me / stop, events_per_s=events / stop,
               y_pp_um=float(np.ptp(r["y"][half])) * 1e6, restitution=math.nan, W_dissipated_J=float(r["W_plastic"][-1]))
    if V is not None:  # a drop: the rebound speed and the kinetic energy lost (damping included)
        row["y_pp_um"] = math.nan
        row["restitution"] = float(r["v"][-1]) / V
        row["W_dissipated_J"] = 0.5 * p["m"] * (V * V - float(r["v"][-1]) ** 2)
    elif scene in WALL_SCENES:  # both walls: the larger peak, the contacts' plastic and damping work
        row["F_max_N"] = max(row["F_max_N"], float(r["F_upper"].max()))
        row["W_dissipated_J"] = float(r["W_dissipated"][-1])
        row.update(walls(r, p, stop, log))
    elif variant in ("hertz_damped", "hunt_crossley", "linear"):
        row["W_dissipated_J"] = math.nan  # the damping's work is no output
    row.update(agreement)
    return row


def run(out_dir, fmu=None, only_scenes=None, variants=None, repeat=1, warned=None):
    """Every scene with every variant (or the ones named): the rows of the table; warned: as measure's.
    The vehicle-track scene
    needs the example's companion FMUs beside the FMU (a checkout's build/). A ValueError naming them
    for names that are not in SCENES or VARIANTS, before anything is written."""
    import shutil

    from fmpy import extract, read_model_description
    unknown = unknown_names(only_scenes or (), SCENES) + unknown_names(variants or (), VARIANTS)
    if unknown:
        raise ValueError(f"unknown scene or variant {', '.join(unknown)}: the scenes are {', '.join(SCENES)}; "
                         f"the variants {', '.join(VARIANTS)}")
    fmu = str(fmu or fmu_path())
    md = read_model_description(fmu)
    unzipdir = extract(fmu)
    profile = out_dir / "corrugation.txt"
    rolling.corrugation(profile)
    rough = None
    if not only_scenes or "vehicle_track" in only_scenes:
        vt_parameters.companion_fmus(pathlib.Path(fmu).parent)
        rough = out_dir / "roughness.txt"
        roughness.write(rough, *roughness.profile(**vt_parameters.ROUGHNESS))
        rough = rough.resolve()
    rows = []
    try:
        for scene, (params, stop, V) in scenes(profile.resolve(), rough).items():
            if only_scenes and scene not in only_scenes:
                continue
            for variant in variants or VARIANTS:
                rows.append(measure(scene, variant, params, stop, V, fmu, md, unzipdir, repeat, warned))
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)
    return rows


def walls(r, p, stop, log=None):
    """What each wall sees in a two-wall run r (the outputs of _events) of parameters p, over its second
    half (settled): {'speed_m_s': the mean speed the sphere leaves a wall with (|v| on the first sample of
    each free flight), 'speed_closed_form': its ratio to cavity_orbit's u for the variant's e_restitution
    (NaN for a law without one, or under gravity or load), 'impacts_lower_per_cycle',
    'impacts_upper_per_cycle', 'F_lower_N', 'F_upper_N' (peak forces),
    'W_cycle_J' (W_dissipated per cycle), 'first_upper_s' (the first contact onset on the upper wall,
    from the event log; NaN without one), 'trace' (the last TRACE_CYCLES cycles for walls_figure)}."""
    half = r["time"] >= stop / 2
    cycles = p["f"] * stop / 2
    free = (r["mode"] == 0) & (r["mode_upper"] == 0)
    onsets = r["n_impacts"] + r["n_impacts_upper"]
    # a flight's first sample: free after a contact, or after a contact that began and ended between samples
    first = free & half & np.concatenate(([False], ~free[:-1] | (onsets[1:] != onsets[:-1])))
    speed = float(np.mean(np.abs(r["v"][first]))) if first.any() else math.nan
    u = math.nan
    if p.get("g", 9.81) == 0.0 and p.get("P", 0.0) == 0.0 and "e_restitution" in p:
        u = cavity_orbit(p["e_restitution"], p["a"], p["f"], p["gap"])[1]
    out = dict(speed_m_s=speed, speed_closed_form=speed / u,
               impacts_lower_per_cycle=float(r["n_impacts"][-1] - r["n_impacts"][half][0]) / cycles,
               impacts_upper_per_cycle=float(r["n_impacts_upper"][-1] - r["n_impacts_upper"][half][0]) / cycles,
               F_lower_N=float(r["F"][half].max()), F_upper_N=float(r["F_upper"][half].max()),
               W_cycle_J=float(r["W_dissipated"][-1] - r["W_dissipated"][half][0]) / cycles,
               first_upper_s=_first_onset(log, "upper") if log is not None else math.nan)
    last = r["time"] >= r["time"][-1] - TRACE_CYCLES / p["f"] - 1e-12
    out["trace"] = {k: np.asarray(r[k][last], float) for k in ("time", "y", "yC", "n_impacts", "n_impacts_upper")}
    out["trace"]["gap"] = p["gap"]
    return out


def _first_onset(log, contact):
    """The time of the first contact onset (a guard event from mode 0) of `contact` ("lower" or "upper")
    in an event log of a run with the upper stop (logEvents: 'event t=T kind=guard guard=G mode=0->M
    delta=D v=V contact=C', delta that contact's own indentation); NaN when none."""
    for _, _, m in log.messages:
        if m.startswith("event t=") and "kind=guard" in m and "mode=0->" in m:
            fields = dict(f.split("=", 1) for f in m.split() if "=" in f)
            if fields.get("contact") == contact:
                return float(fields["t"])
    return math.nan


def unknown_names(names, known):
    """The names that are not in known, in the order given."""
    return [n for n in names if n not in known]


def write_csv(path, rows):
    """The rows' COLUMNS, and the two-wall scenes' WALL_KEYS when a row has them (empty in the others)."""
    columns = COLUMNS + [k for k in WALL_KEYS if any(k in r for r in rows)]
    with replacing(path) as f:
        f.write(",".join(columns) + "\n")
        for r in rows:
            cells = [r[c] if c in COLUMNS else r.get(c, math.nan) for c in columns]
            f.write(",".join(c if isinstance(c, str) else f"{c:.6g}" for c in cells) + "\n")


def markdown(rows):
    """The table doc/choosing.md quotes."""
    head = ["scene", "variant", "F_max [N]", "restitution", "dissipated [J]", "y p-p [um]", "events",
            "CPU CS [s/s]", "CPU ME [s/s]", "events/s"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [r["scene"], r["variant"], f"{r['F_max_N']:.4g}", _num(r["restitution"], "{:.4f}"),
                 _num(r["W_dissipated_J"], "{:.3g}"), _num(r["y_pp_um"], "{:.3g}"), str(r["events"]),
                 _cpu_cell(r["cpu_cs_s_per_s"]), _cpu_cell(r["cpu_me_s_per_s"]), f"{r['events_per_s']:.3g}"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def agreement_markdown(rows):
    """The vehicle-track scene's Model Exchange master against its co-simulation (vt_agreement), a row per
    variant; empty when no row has it."""
    keys = [f"me_vs_cs_{h:g}" for h in AGREEMENT_STEPS]
    have = [r for r in rows if all(k in r for k in keys)]
    if not have:
        return ""
    head = ["variant"] + [f"step {h:g} s" for h in AGREEMENT_STEPS]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join([r["variant"]] + [f"{r[k]:.2g}" for k in keys]) + " |" for r in have]
    return "\n".join(lines) + "\n"


WALL_KEYS = ("speed_m_s", "speed_closed_form", "impacts_lower_per_cycle", "impacts_upper_per_cycle", "F_lower_N",
             "F_upper_N", "W_cycle_J")


def walls_markdown(rows):
    """The two-wall scenes over their settled second half (walls()), a row per scene and variant; empty
    when no row has them."""
    have = [r for r in rows if all(k in r for k in WALL_KEYS)]
    if not have:
        return ""
    head = ["scene", "variant", "leaves a wall at [m/s]", "/ closed form", "impacts per cycle, lower", "upper",
            "peak force, lower [N]", "upper [N]", "dissipated per cycle [mJ]"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in have:
        cells = [r["scene"], r["variant"], _num(r["speed_m_s"], "{:.4g}"), _num(r["speed_closed_form"], "{:.4f}"),
                 f"{r['impacts_lower_per_cycle']:.2g}", f"{r['impacts_upper_per_cycle']:.2g}", f"{r['F_lower_N']:.4g}",
                 f"{r['F_upper_N']:.4g}", f"{1e3 * r['W_cycle_J']:.3g}"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _num(x, fmt):
    return "" if x != x else fmt.format(x)


def _cpu_cell(x):
    """A CPU time; NaN is a run that failed (the command printed why)."""
    return "failed" if x != x else f"{x:.2g}"


# each variant's look in the figure: colour, marker, line style (no two alike, so that curves that
# cross or run close stay apart)
STYLES = {"hertz": ("C0", "o", "-"), "johnson": ("C1", "s", "-"), "johnson_continuous": ("C2", "^", "--"),
          "johnson_moving": ("C3", "v", ":"), "lepp": ("C4", "D", "-"), "thornton": ("C5", "P", "--"),
          "hertz_damped": ("C6", "X", "-"), "hunt_crossley": ("C7", "*", "--"), "linear": ("C8", "h", ":")}
COINCIDE = 1e-3   # restitutions closer than this at every speed are one curve (0.3 px on the drawn axis)
COST_TITLES = {"fig4b": "paper's harmonic excitation (Fig. 4b)", "vehicle_track": "vehicle-track example"}


def drop_curves(rows):
    """The drops' restitution against the impact speed: [(label, variant of the look, speeds, restitutions)],
    one per curve; variants whose restitutions agree within COINCIDE at every speed share one curve,
    labelled with every name ('hertz = johnson_moving'), so that none lies hidden under another."""
    curves = []
    for variant in VARIANTS:
        pts = sorted((float(r["scene"][5:]), r["restitution"]) for r in rows
                     if r["variant"] == variant and r["scene"].startswith("drop"))
        if not pts:
            continue
        x, y = (np.array(c) for c in zip(*pts))
        for c in curves:
            if np.array_equal(c[2], x) and np.allclose(c[3], y, rtol=0, atol=COINCIDE, equal_nan=True):
                c[0].append(variant)
                break
        else:
            curves.append(([variant], variant, x, y))
    return [(" = ".join(names), look, x, y) for names, look, x, y in curves]


def figure(rows):
    """Left: the drops' restitution against the impact speed, one curve per variant (those that coincide
    share one, named together). Right, for the paper's harmonic excitation (fig4b) and the vehicle-track
    example, one row each: every variant's peak force relative to hertz's, and its CPU per simulated
    second in Co-Simulation (bars from zero; "failed" where the run failed)."""
    from .plotting import pyplot
    plt = pyplot()
    costs = [s for s in ("fig4b", "vehicle_track") if any(r["scene"] == s for r in rows)]
    fig = plt.figure(figsize=(14, 1.0 + 3.6 * max(len(costs), 1.3)), layout="constrained")
    grid = fig.add_gridspec(max(len(costs), 1), 3, width_ratios=[1.3, 1, 1])
    a = fig.add_subplot(grid[:, 0])
    for label, look, x, y in drop_curves(rows):
        color, marker, ls = STYLES[look]
        a.plot(x, y, color=color, marker=marker, ls=ls, ms=7, label=label)
    a.set(xscale="log", xlabel="impact speed [m/s]", ylabel="restitution (rebound / impact speed)",
          ylim=(0, 1.05), title="drop of a steel sphere")
    a.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncols=2, fontsize=8)
    for k, scene in enumerate(costs):
        draw_costs(fig.add_subplot(grid[k, 1]), fig.add_subplot(grid[k, 2]), rows, scene)
    return fig


def draw_costs(force_ax, cpu_ax, rows, scene):
    """One scene's peak force / hertz's and CPU per simulated second (Co-Simulation), a bar per variant."""
    mine = {r["variant"]: r for r in rows if r["scene"] == scene}
    names = [v for v in VARIANTS if v in mine]
    base = mine["hertz"]["F_max_N"] if "hertz" in mine else math.nan
    pos = np.arange(len(names))
    colors = [STYLES[v][0] for v in names]
    force_ax.barh(pos, [mine[v]["F_max_N"] / base for v in names], color=colors)
    force_ax.axvline(1.0, color="k", lw=0.6, ls=":")
    cpu = [mine[v]["cpu_cs_s_per_s"] for v in names]
    cpu_ax.barh(pos, np.nan_to_num(cpu), color=colors)
    for y, c in zip(pos, cpu):
        if c != c:
            cpu_ax.text(0, y, " failed", va="center", fontsize=8)
    force_ax.set(yticks=pos, yticklabels=names, ylabel="variant", xlabel="peak force / hertz's", xlim=(0, None),
                 title=f"{COST_TITLES[scene]}: peak force")
    cpu_ax.set(yticks=pos, yticklabels=[], xlabel="CPU per simulated second, Co-Simulation [s/s]", xlim=(0, None),
               title=f"{COST_TITLES[scene]}: cost")
    for ax in (force_ax, cpu_ax):
        ax.invert_yaxis()   # the variants top down, in the table's order
        ax.tick_params(labelsize=8)
        ax.title.set_size(9)


# the variants walls_figure draws the sphere of: the damper's law of choice and the paper's plastic law
TRACE_VARIANTS = ("hertz_damped", "johnson")
WALL_TITLES = {"impact_damper": "impact damper: a cavity 10 mm high, no gravity",
               "clearance": "clearance of 0.5 mm under gravity (backlash)"}


def walls_figure(rows):
    """The two-wall scenes, a panel each: the lower wall yC, the upper wall yC + gap and the sphere's y over
    the last TRACE_CYCLES cycles, for each variant of TRACE_VARIANTS that ran (the first one that did when
    none), each contact onset marked on the wall it hits (^ the lower, v the upper). None when no row has
    a trace."""
    from .plotting import draw_walls, figure_legend, pyplot
    traced = [r for r in rows if "trace" in r]
    scenes = [s for s in WALL_SCENES if any(r["scene"] == s for r in traced)]
    if not scenes:
        return None
    plt = pyplot()
    fig, axes = plt.subplots(1, len(scenes), figsize=(6.5 * len(scenes), 4.6), layout="constrained", squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        mine = {r["variant"]: r for r in traced if r["scene"] == scene}
        names = [v for v in TRACE_VARIANTS if v in mine] or [next(iter(mine))]
        draw_walls(ax, mine[names[0]]["trace"], [(v, mine[v]["trace"], STYLES[v][0], STYLES[v][2]) for v in names],
                   f=SHAKEN["f"])
        ax.set_title(WALL_TITLES[scene], fontsize=10)
    figure_legend(fig, axes[0], ncols=4, fontsize=8)
    return fig
