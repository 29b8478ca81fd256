"""The damped Hertz, linear spring-dashpot and Thornton laws through the FMU against closed forms and the
independent reference (vibroimpact.reference.laws, written from the equations): a steel sphere dropped on
a steel plane (one impact, no load), in Co-Simulation with every solver and in Model Exchange; the FMI 3.0
enumeration items; refusals; an FMU state saved inside a damped contact."""
import math
import pathlib
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi1 import FMICallException

from conftest import BUILD
from solvers import each_solver
from vibroimpact.me import run_me
from vibroimpact.reference import laws as L
from vibroimpact.reference.closed_forms import effective

HERTZ_DAMPED, LINEAR, THORNTON = 4, 5, 6
# the steel sphere of Johnson's Hertz case: R = 10 mm, 32.88 g, on a steel plane (E, nu: the FMU's defaults)
STEEL = dict(R1=0.01, R2=0.0, m=0.03288, Y=1e9, theta_Y=1.1, P=0.0, g=0.0, init=2)
SPEEDS = (0.01, 0.3, 3.0)  # m/s
TARGETS = (0.2, 0.6, 0.95)
K_SPRING = 1e7  # N/m


def drop(fmu_path, law, V, solver=None, **params):
    """One impact at V [m/s]: (rebound speed / V, result). The stop time covers the contact several times."""
    p = dict(STEEL, contact_model=law, v0=-V, rtol=1e-10, **params)
    if solver is not None:
        p["solver"] = solver
    r = simulate_fmu(fmu_path, start_values=p, stop_time=5e-3, output_interval=5e-4,
                     output=["v", "mode", "n_impacts", "F", "delta_c", "delta_f", "Rbar", "W_plastic"])
    assert r["mode"][-1] == 0 and r["F"][-1] == 0.0 and r["n_impacts"][-1] == 0
    return r["v"][-1] / V, r


@pytest.mark.timeout(300)
@each_solver
@pytest.mark.parametrize("law", [HERTZ_DAMPED, LINEAR], ids=["exact", "linear"])
def test_exact_restitution_at_every_speed(fmu_path, solver, law):
    """damping_formula = exact and the linear spring-dashpot rebound at e_restitution to 1e-6, 0.01-3 m/s."""
    for e in TARGETS:
        for V in SPEEDS:
            ratio, _ = drop(fmu_path, law, V, solver, e_restitution=e, damping_formula=1, k_spring=K_SPRING)
            assert ratio == pytest.approx(e, abs=1e-6), (e, V)


def test_exact_restitution_across_e(fmu_path):
    """damping_formula = exact (alpha from its table) rebounds at e_restitution to 1e-7 of the impact
    speed, at e drawn at random (log-uniform over [1e-3, 1)), at the table's ends and next to 1."""
    rng = np.random.default_rng(41)
    for e in [1e-3, 0.999999, 1.0 - 1e-9, *10.0 ** rng.uniform(-3.0, 0.0, 8)]:
        ratio, _ = drop(fmu_path, HERTZ_DAMPED, 0.3, 3, e_restitution=e, damping_formula=1)
        assert ratio == pytest.approx(e, abs=1e-7), e


@pytest.mark.timeout(300)
@each_solver
@pytest.mark.parametrize("formula", sorted(L.FORMULAS), ids=list(L.FORMULAS[f] for f in sorted(L.FORMULAS)))
def test_published_forms_match_the_reference(fmu_path, solver, formula):
    """Hunt-Crossley, Lankarani-Nikravesh, Flores: the restitution of Hunt and Crossley's relation
    chi (1 + e_a) = ln((1 + chi)/(1 - chi e_a)), which the reference's integration reproduces."""
    for e in (0.3, 0.9):
        expected = L.hc_restitution_closed_form(L.chi(formula, e))
        for V in (0.01, 3.0):
            ratio, _ = drop(fmu_path, HERTZ_DAMPED, V, solver, e_restitution=e, damping_formula=formula)
            assert ratio == pytest.approx(expected, abs=1e-6), (e, V)


def thornton_yield_speed():
    """V_Y of the steel drop: 1/2 m V_Y^2 = 2/5 F_Y delta_Y, with the FMU's yield limit (closed_forms)."""
    e = effective(STEEL)
    return math.sqrt(0.8 * e["F_Y"] * e["delta_Y"] / STEEL["m"]), e


@pytest.mark.timeout(300)
@each_solver
def test_thornton_restitution_closed_form(fmu_path, solver):
    """Thornton's closed form to 1e-5 from just above the yield speed to 30 times it; below it, elastic.
    The peak force F* = F_Y + 1.5 F_Y/delta_Y (delta* - delta_Y) and delta* from the loading work."""
    VY, e = thornton_yield_speed()
    for k in (1.01, 1.5, 4.0, 30.0):
        ratio, r = drop(fmu_path, THORNTON, k * VY, solver)
        # rtol 1e-10: within 1.3e-8 of the closed form with every solver (measured, the worst of the 16 runs)
        assert ratio == pytest.approx(L.thornton_restitution(1 / k), abs=2e-7), k
        # work 1/2 m V^2 = 2/5 F_Y dY + F_Y x + 3/4 F_Y/dY x^2, x = delta* - delta_Y
        F, dY, W = e["F_Y"], e["delta_Y"], 0.5 * STEEL["m"] * (k * VY) ** 2
        x = (-F + math.sqrt(F * F + 3 * F / dY * (W - 0.4 * F * dY))) / (1.5 * F / dY)
        assert r["delta_c"][-1] == pytest.approx(dY + x, rel=1e-6)
        assert r["W_plastic"][-1] == pytest.approx(W * (1 - L.thornton_restitution(1 / k) ** 2), rel=1e-6)
    ratio, r = drop(fmu_path, THORNTON, 0.5 * VY, solver)
    assert ratio == pytest.approx(1.0, abs=1e-6) and r["W_plastic"][-1] == 0.0


@pytest.mark.timeout(120)
def test_contact_time_and_peak_force(fmu_path):
    """The linear law's contact time (closed form, omega t_c = (pi - 2 asin zeta)/cos(asin zeta)) and the
    exact law's peak force against the reference's integration (x_max, f_max of the Tsuji impact)."""
    e, V, m = 0.6, 1.0, STEEL["m"]
    zeta = L.linear_zeta(e)
    tc = L.linear_contact_time(zeta) / math.sqrt(K_SPRING / m)
    dt = tc / 2000
    p = dict(STEEL, contact_model=LINEAR, v0=-V, rtol=1e-10, e_restitution=e, k_spring=K_SPRING)
    r = simulate_fmu(fmu_path, start_values=p, stop_time=1.5 * tc, output_interval=dt, output=["F", "contact"])
    t_on = r["time"][r["contact"] > 0]
    assert t_on[-1] + dt == pytest.approx(tc, abs=1.01 * dt)
    ek = effective(STEEL)
    alpha = L.tsuji_alpha(e)
    _, tau, _, f_max = L.tsuji_impact(alpha)
    d0 = (m * V * V / ek["K"]) ** 0.4
    t_c = tau * d0 / V
    p = dict(STEEL, contact_model=HERTZ_DAMPED, v0=-V, rtol=1e-10, e_restitution=e)
    r = simulate_fmu(fmu_path, start_values=p, stop_time=1.2 * t_c, output_interval=t_c / 4000, output=["F"])
    # the largest sample on the grid of t_c/4000 lies below the peak by up to 0.75 (pi/8000)^2 = 1.2e-7 of it
    # (F ~ sin^1.5 near the top); measured 4.8e-9 with the worst solver (bdf) at rtol 1e-10
    assert r["F"].max() == pytest.approx(f_max * ek["K"] * d0 ** 1.5, rel=1e-6)


@pytest.mark.timeout(300)
@pytest.mark.parametrize("law, params", [(HERTZ_DAMPED, dict(damping_formula=1)), (HERTZ_DAMPED, dict(damping_formula=3)),
                                         (LINEAR, dict(k_spring=K_SPRING)), (THORNTON, {})],
                         ids=["exact", "lankarani_nikravesh", "linear", "thornton"])
def test_model_exchange_drop(fmu_path, law, params):
    """Model Exchange (fmpy's CVode, the FMU's event indicators and Jacobian): the same restitutions."""
    VY, _ = thornton_yield_speed()
    for V in (0.05, 2.0):
        p = dict(STEEL, contact_model=law, v0=-V, e_restitution=0.6, **params)
        r, _ = run_me(fmu_path, p, 5e-3, rtol=1e-10, output=("v", "mode"))
        assert r["mode"][-1] == 0
        if law == THORNTON:
            expected = L.thornton_restitution(VY / V)
        elif params.get("damping_formula", 1) != 1:
            expected = L.hc_restitution_closed_form(L.chi(params["damping_formula"], 0.6))
        else:
            expected = 0.6
        # fmpy's CVode at rtol 1e-10 integrates here: within 1.5e-8 of the closed forms (measured); 1e-6
        # leaves room for another fmpy's CVode
        assert r["v"][-1] / V == pytest.approx(expected, abs=1e-6), V


def test_fmi3_lists_the_new_items():
    """Both model descriptions carry the new items and parameters (FMI 3.0: Enumeration types)."""
    with zipfile.ZipFile(pathlib.Path(BUILD) / "fmi3" / "VibroImpact.fmu") as z:
        md3 = ET.ElementTree(ET.fromstring(z.read("modelDescription.xml")))
    items = {t.get("name"): {i.get("name"): int(i.get("value")) for i in t.iter("Item")}
             for t in md3.getroot().iter("EnumerationType")}
    assert {"hertz_damped": 4, "linear": 5, "thornton": 6}.items() <= items["ContactModel"].items()
    assert items["DampingFormula"] == {"exact": 1, "hunt_crossley": 2, "lankarani_nikravesh": 3, "flores": 4}
    names = {v.get("name") for v in md3.getroot().find("ModelVariables")}
    assert {"e_restitution", "damping_formula", "k_spring"} <= names


def test_refusals(fmu_path, unzipdir, model_description):
    """Values the laws cannot take are refused when set (ranges) or at initialization (what a range
    cannot say), naming the variable."""
    vr = {v.name: v.valueReference for v in model_description.modelVariables}
    fmu = FMU2Slave(guid=model_description.guid, unzipDirectory=unzipdir,
                    modelIdentifier=model_description.coSimulation.modelIdentifier, instanceName="refusals")
    fmu.instantiate()
    try:
        for name, value in (("e_restitution", 0.0), ("e_restitution", 1.5), ("k_spring", 0.0), ("k_spring", -1.0)):
            with pytest.raises(FMICallException):
                fmu.setReal([vr[name]], [value])
        with pytest.raises(FMICallException):
            fmu.setInteger([vr["damping_formula"]], [5])
        fmu.setInteger([vr["contact_model"]], [HERTZ_DAMPED])
        fmu.setReal([vr["e_restitution"]], [1e-300])  # in range, but no exact damping reaches it
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        with pytest.raises(FMICallException):
            fmu.exitInitializationMode()
    finally:
        fmu.freeInstance()


INTEGERS = ("contact_model", "damping_formula", "init", "solver")


def initialized(fmu, vr, params):
    """Set the parameters of an instantiated FMU2Slave and leave initialization mode."""
    for name, value in params.items():
        if name in INTEGERS:
            fmu.setInteger([vr[name]], [int(value)])
        else:
            fmu.setReal([vr[name]], [float(value)])
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()


@pytest.mark.timeout(120)
@each_solver
@pytest.mark.parametrize("formula", [1, 2])
def test_state_saved_inside_a_damped_contact(fmu_path, unzipdir, model_description, solver, formula):
    """An FMU state taken during the contact (V_i, the onset's speed, is part of it) continues bit for
    bit like the run that saved it, with every solver."""
    vr = {v.name: v.valueReference for v in model_description.modelVariables}
    fmu = FMU2Slave(guid=model_description.guid, unzipDirectory=unzipdir,
                    modelIdentifier=model_description.coSimulation.modelIdentifier, instanceName="state")
    fmu.instantiate()
    try:
        initialized(fmu, vr, dict(STEEL, contact_model=HERTZ_DAMPED, damping_formula=formula, v0=-1.0,
                                  e_restitution=0.5, rtol=1e-10, solver=solver))
        fmu.doStep(0.0, 2e-5)
        assert fmu.getReal([vr["F"]])[0] > 0.0  # inside the contact
        state = fmu.serializeFMUstate(fmu.getFMUstate())
        fmu.doStep(2e-5, 1e-3)
        first = fmu.getReal([vr["v"], vr["y"]])
        fmu.setFMUstate(fmu.deSerializeFMUstate(state))
        fmu.doStep(2e-5, 1e-3)
        assert fmu.getReal([vr["v"], vr["y"]]) == first
        assert first[0] == pytest.approx(0.5 if formula == 1 else L.hc_restitution(formula, 0.5), abs=1e-6)
    finally:
        fmu.terminate()
        fmu.freeInstance()


def _warnings(logged, vr, params):
    from conftest import start
    inst = logged()
    s = inst.instantiate(logging=False)
    s.setDebugLogging(True, ["logStatusWarning"])
    start(s, vr, params)
    s.doStep(0.0, 1e-5)
    return [m for status, cat, m in inst.messages if status == 1 and cat == "logStatusWarning"]


@pytest.mark.parametrize("formula, e, warn", [(2, 0.3, 0.5813), (3, 0.3, 0.6842), (4, 0.3, 0.2562), (4, 0.9, None),
                                              (1, 0.3, None)])
def test_published_form_outside_its_range_warns(logged, vr, formula, e, warn):
    """A published form whose restitution misses e_restitution by more than 0.01 says what it gives
    (the reference's values); exact damping and Flores at 0.9 (0.8939) do not warn."""
    w = _warnings(logged, vr, dict(STEEL, contact_model=HERTZ_DAMPED, damping_formula=formula, e_restitution=e, v0=-1.0))
    named = [m for m in w if "gives an isolated impact the restitution" in m]
    if warn is None:
        assert named == [], w
    else:
        assert len(named) == 1 and f"restitution {warn:.4f}, not e_restitution = {e:g}" in named[0], w


def test_damping_formula_of_another_law_warns(logged, vr):
    w = _warnings(logged, vr, dict(contact_model=1, damping_formula=2))
    assert len(w) == 1 and "damping_formula is ignored" in w[0], w


# the paper's harmonic excitation (Fig. 4b: a = 0.1 mm, f = 560 Hz) with each new law, and the modes each reaches
JACOBIAN_CASES = {"exact": (dict(contact_model=HERTZ_DAMPED, damping_formula=1), [0, 1]),
                  # a touching start: the first contact has an impact speed (a static one is undamped)
                  "hunt_crossley": (dict(contact_model=HERTZ_DAMPED, damping_formula=2, init=2, v0=-0.1), [0, 1]),
                  "linear": (dict(contact_model=LINEAR), [0, 1]),
                  "thornton": (dict(contact_model=THORNTON), [0, 1, 2, 3])}


@pytest.mark.timeout(300)
@pytest.mark.parametrize("case", JACOBIAN_CASES)
def test_jacobian_of_the_new_laws(case, fmu_path, unzipdir, model_description):
    """fmi2GetDirectionalDerivative against finite differences in every mode the law reaches (the check of
    test_me_jacobian.py); the damped laws' force depends on v, and that partial is declared."""
    from fmpy import simulate_fmu
    from test_me_jacobian import Probe, check_point, declared, unknowns
    from vibroimpact.me import MeInstance
    params, modes = JACOBIAN_CASES[case]
    md = model_description
    names, deps = unknowns(md), declared(md)
    inst = MeInstance(fmu_path, unzipdir, md)
    fmu = inst.instantiate(categories=())
    probe, seen, record = Probe(inst), set(), set()

    def step_finished(time, recorder):
        mode = fmu.getInteger([inst.vr["mode"]])[0]
        if mode not in seen and time > 0.0 and check_point(probe, md, names, deps, record):
            seen.add(mode)
        return len(seen) < len(modes)

    simulate_fmu(str(fmu_path), fmi_type="ModelExchange", solver="CVode", stop_time=0.02, relative_tolerance=1e-9,
                 start_values=dict(params, a=1e-4, f=560.0, e_restitution=0.6), output_interval=1e-5, fmu_instance=fmu,
                 model_description=md, step_finished=step_finished, output=["y"])
    fmu.freeInstance()
    assert not inst.errors(), inst.errors()
    assert seen == set(modes), seen
    assert ("der_v", "y") in record
    if case != "thornton":
        assert ("der_v", "v") in record and ("F", "v") in record


@pytest.mark.timeout(300)
@each_solver
@pytest.mark.parametrize("formula", [1, 2, 4])
def test_bounce_under_gravity_against_the_reference_model(fmu_path, solver, formula):
    """The sphere leaves the plane at 0.5 m/s and lands under gravity: that landing is a new contact,
    damped with its own approach speed (V_i); the FMU follows the independent reference model
    (vibroimpact.reference.model) to 1e-7 m/s."""
    from vibroimpact.reference import model as M
    p = dict(STEEL, contact_model=HERTZ_DAMPED, damping_formula=formula, e_restitution=0.6, v0=0.5, g=9.81)
    r = simulate_fmu(fmu_path, start_values=dict(p, rtol=1e-10, solver=solver), stop_time=0.15, output_interval=1e-3,
                     output=["v", "n_impacts"])
    ref = M.simulate(p, t_end=0.15, rtol=1e-11, t_eval=r["time"])
    assert r["n_impacts"][-1] == ref.n_impacts_total == 1
    assert r["v"][-1] == pytest.approx(ref.v[-1], abs=1e-7)
    assert -r["v"][-1] < 0.5  # it lost energy


@pytest.mark.timeout(300)
@each_solver
@pytest.mark.parametrize("law, params", [(HERTZ_DAMPED, dict(damping_formula=1)), (HERTZ_DAMPED, dict(damping_formula=2)),
                                         (LINEAR, {}), (THORNTON, {})],
                         ids=["exact", "hunt_crossley", "linear", "thornton"])
def test_paper_excitation_against_the_reference_model(fmu_path, solver, law, params):
    """The paper's Fig. 4b excitation (a = 0.1 mm, f = 560 Hz, Y = 600 MPa) with each new law, 20 ms
    (11 impacts), against the independent reference model: the same impacts, y to 1e-9 m, F to 1e-5
    of its peak."""
    from vibroimpact.reference import model as M
    p = dict(contact_model=law, Y=6e8, a=1e-4, f=560.0, e_restitution=0.6, **params)
    r = simulate_fmu(fmu_path, start_values=dict(p, rtol=1e-10, solver=solver), stop_time=0.02, output_interval=1e-5,
                     output=["y", "F", "n_impacts"])
    ref = M.simulate(p, t_end=0.02, rtol=1e-11, t_eval=r["time"])
    assert list(r["n_impacts"]) == list(ref.n_impacts) and ref.n_impacts_total >= 10
    assert abs(r["y"] - ref.y).max() < 1e-9
    assert abs(r["F"] - ref.F).max() < 1e-5 * abs(ref.F).max()


@pytest.mark.timeout(120)
@pytest.mark.parametrize("law, params", [(LINEAR, dict(k_spring=K_SPRING)), (HERTZ_DAMPED, dict(damping_formula=1))],
                         ids=["linear", "exact"])
def test_state_saved_in_free_flight_after_a_release(fmu_path, unzipdir, model_description, law, params):
    """After a release the mass is free while the bodies still overlap (delta > 0): an FMU state taken
    there is accepted, serialized or not, and continues bit for bit."""
    vr = {v.name: v.valueReference for v in model_description.modelVariables}
    fmu = FMU2Slave(guid=model_description.guid, unzipDirectory=unzipdir,
                    modelIdentifier=model_description.coSimulation.modelIdentifier, instanceName="free")
    fmu.instantiate()
    try:
        initialized(fmu, vr, dict(STEEL, contact_model=law, v0=-1.0, e_restitution=0.3, rtol=1e-10, **params))
        t, h = 0.0, 1e-6
        while not (fmu.getInteger([vr["mode"]])[0] == 0 and fmu.getReal([vr["delta"]])[0] > 0.0):
            assert t < 1e-3, "no release within 1 ms"
            fmu.doStep(t, h)
            t += h
        state = fmu.getFMUstate()
        blob = fmu.serializeFMUstate(state)
        fmu.doStep(t, 1e-3)
        first = fmu.getReal([vr["v"], vr["y"]])
        fmu.setFMUstate(state)
        fmu.doStep(t, 1e-3)
        assert fmu.getReal([vr["v"], vr["y"]]) == first
        fmu.setFMUstate(fmu.deSerializeFMUstate(blob))
        fmu.doStep(t, 1e-3)
        assert fmu.getReal([vr["v"], vr["y"]]) == first
        assert first[0] == pytest.approx(0.3, abs=1e-8)  # rtol 1e-10: 6.8e-10 off e (measured, every solver)
    finally:
        fmu.terminate()
        fmu.freeInstance()
