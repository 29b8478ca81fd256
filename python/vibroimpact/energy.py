"""The energy balance of a run of the contact FMU (doc/model.md, section 3, "Energy"), from its outputs.

Along a run, the kinetic energy 1/2 m v^2 + E_contact + W_dissipated changes by the work done on the mass
and its contact: the platform's, integral of F yC' dt, and the net load's, -integral of W(t) v dt with
W = P + m g - F_ext. Both works come here from outputs the FMU gives at small communication steps, not
from its energy outputs:
  - a drop (the platform at rest, F_ext constant): the platform does no work, the load's is -W (y - y0);
  - the internal harmonic excitation yC = a (cos(2 pi f t) - 1): by m v' = F - W, the platform's work is
    m [v yC'] - m integral(v yC'' dt) + W [yC], whose integrand v yC'' is continuous (v does not jump),
    so the trapezoid rule converges as h^2 also where F jumps (the linear law's onsets, the paper
    unloading's force drop at a turning point), where the trapezoid rule on F yC' does not;
  - a platform input moved on straight lines without jumps (slope s over a communication step h): the
    platform's work over the step is s F_mean h, F_mean h being the step's impulse.
The balance error is the largest difference between the two sides over the run, relative to the energy
exchanged there: integral of |F yC'| + |W v| dt.

Scenes: `drop` (the paper's wheel touching the rail at t = 0 at 1 m/s downwards, under its load P + m g)
and `fig4b` (the paper's Fig. 4b excitation, a = 0.1 mm at 560 Hz, from the static start), each for every
variant of VARIANTS, in Co-Simulation and Model Exchange (fmpy's CVode), FMI 2.0 and 3.0.
"""
import math

import numpy as np

from . import laws_guide
from .fmu import MessageLog, fmu3_path, fmu_path, logged_instance
from .laws_guide import E_DAMPED

# the variants of the guide to the laws (vibroimpact.laws_guide), with the damped Hertz forms not there
VARIANTS = dict(laws_guide.VARIANTS,
                lankarani_nikravesh=dict(contact_model=4, damping_formula=3, e_restitution=E_DAMPED),
                flores=dict(contact_model=4, damping_formula=4, e_restitution=E_DAMPED))
SCENES = {
    "drop": dict(init=2, v0=-1.0),
    "fig4b": dict(a=1e-4, f=560.0),
}
INTERFACES = [("CoSimulation", 2), ("CoSimulation", 3), ("ModelExchange", 2), ("ModelExchange", 3)]
OUTPUTS = ["v", "y", "yC", "F", "E_contact", "W_dissipated"]
M, P, G = 407.747, 40000.0, 9.81  # the model description's start values of m, P, g


def load(params):
    """m [kg] and the net load W = P + m g [N] of a run's parameters (F_ext = 0)."""
    m = params.get("m", M)
    return m, params.get("P", P) + m * params.get("g", G)


def harmonic_platform_work(r, m, W, a, f):
    """The work integral of F yC' dt of the platform yC = a (cos(2 pi f t) - 1) along the samples r (time,
    v, yC), from m v' = F - W: m [v yC'] - m integral(v yC'') + W [yC] (trapezoid rule)."""
    t, v, w = r["time"], r["v"], 2.0 * math.pi * f
    dyC, ddyC = -a * w * np.sin(w * t), -a * w * w * np.cos(w * t)
    q = v * ddyC
    inner = np.concatenate([[0.0], np.cumsum(0.5 * (q[1:] + q[:-1]) * np.diff(t))])
    return m * (v * dyC - v[0] * dyC[0]) - m * inner + W * (r["yC"] - r["yC"][0])


def balance_error(r, m, platform_work, load_work, exchanged):
    """max |1/2 m v^2 + E_contact + W_dissipated - (their start) - platform work - load work| / exchanged."""
    E = 0.5 * m * r["v"] ** 2 + r["E_contact"] + r["W_dissipated"]
    return float(np.max(np.abs(E - E[0] - platform_work - load_work))) / exchanged


def scene_balance(r, params):
    """The relative balance error of a run of one of the SCENES (parameters params) sampled in r."""
    m, W = load(params)
    t, dt = r["time"], np.diff(r["time"])
    load_work = -W * (r["y"] - r["y"][0])
    a = params.get("a", 0.0)
    if a == 0.0:
        platform, power = np.zeros_like(t), np.zeros_like(t)
    else:
        w = 2.0 * math.pi * params.get("f", 560.0)
        platform, power = harmonic_platform_work(r, m, W, a, params.get("f", 560.0)), r["F"] * a * w * np.sin(w * t)
    exchanged = float(np.sum((np.abs(power[1:]) + np.abs(W * r["v"][1:])) * dt))
    return balance_error(r, m, platform, load_work, exchanged)


def run(variant, scene, interface="CoSimulation", version=2, rtol=1e-9, stop=0.01, h=1e-6, fmu=None,
        warned=None):
    """Samples (fmpy's result) of a variant in a scene through the FMU, every h up to stop; its parameters.
    warned: called with the FMU's warnings when it logged any (vibroimpact.fmu.Relay)."""
    import shutil

    from fmpy import extract, read_model_description, simulate_fmu
    params = dict(VARIANTS[variant], **SCENES[scene], rtol=rtol)
    path = str(fmu or (fmu_path() if version == 2 else fmu3_path()))
    options = dict(solver="CVode", relative_tolerance=rtol) if interface == "ModelExchange" else {}
    md, unzipdir = read_model_description(path), extract(path)
    instance, log = logged_instance(md, unzipdir, interface, name="energy")
    try:
        r = simulate_fmu(unzipdir, fmi_type=interface, start_values=params, stop_time=stop, output_interval=h,
                         output=OUTPUTS, model_description=md, fmu_instance=instance, **options)
    finally:
        instance.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)
    if warned is not None and log.warnings():
        warned(log.warnings())
    return r, params


def table(variants=None, scenes=None, interfaces=None, warned=None, **options):
    """Rows (variant, scene, [relative balance error per interface of `interfaces`]); warned: called with
    ('VARIANT SCENE INTERFACE', the FMU's warnings) when it logged any in a run (a fmu.Relay)."""
    interfaces = interfaces or INTERFACES
    rows = []
    for variant in variants or VARIANTS:
        for scene in scenes or SCENES:
            errors = []
            for interface, version in interfaces:
                what = f"{variant} {scene} {'CS' if interface == 'CoSimulation' else 'ME'} FMI {version}.0"
                r, params = run(variant, scene, interface, version,
                                warned=warned and (lambda texts: warned(what, texts)), **options)  # noqa: B023
                errors.append(scene_balance(r, params))
            rows.append((variant, scene, errors))
    return rows


def vehicle_track_balance(variant, step=1e-5, stop=0.02, v0=-0.5, build=None, warned=None):
    """The contact FMU's balance in the vehicle-track example (vibroimpact.vehicle_track.master.run):
    the wheel (the contact FMU's mass) set onto the rail at v0 with the vehicle on it, Gauss-Seidel
    vehicle, track, contact, the rail's displacement handed as a straight line from its value at the
    step's start to that at its end (the track has stepped: no jump), the vehicle's force held. Over
    step k the platform does s_k F_mean h (s_k the line's slope), the load (F_ext - m g) (y_k+1 - y_k).
    warned: called with the contact FMU's warnings when it logged any (a fmu.Relay's lambda)."""
    from .vehicle_track import master
    log = MessageLog(limit=200, unique=True)   # warnings and errors only: no event log
    r = master.run(step, stop, order=("vehicle", "track", "contact"), rail_motion="ramp", build=build,
                   rtol=1e-9, contact=dict(VARIANTS[variant], init=2, v0=v0),
                   record=("E_contact", "W_dissipated"), contact_log=log, contact_events=False)
    if warned is not None and log.warnings():
        warned(log.warnings())
    m, g = master.parameters.WHEEL["m"], master.parameters.WHEEL["g"]
    slope = np.diff(r["track.z_rail"]) / step
    F_ext = r["vehicle.F_wheel"][1:]  # the vehicle steps first: its new force acts over the contact's step
    dy = np.diff(r["contact.y"])
    platform = slope * r["contact.F_mean"][1:] * step
    load_ = (F_ext - m * g) * dy
    work = np.concatenate([[0.0], np.cumsum(platform + load_)])
    c = {"v": r["contact.v"], "E_contact": r["contact.E_contact"], "W_dissipated": r["contact.W_dissipated"]}
    exchanged = float(np.sum(np.abs(platform) + np.abs(load_)))
    return balance_error(c, m, work, 0.0, exchanged), r
