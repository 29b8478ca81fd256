"""fmi2GetDirectionalDerivative against finite differences, in every mode of every law.

Each case runs a paper scenario (or a damped law under Fig. 4b's excitation) in Model Exchange
(fmpy's CVode) and, at the first completed step in each mode it reaches, with the instance in
continuous-time mode: takes an FMU state, then for every known (the states y, v, W_damping and the
inputs yC_in, F_ext) compares the FMU's partial derivatives of
every unknown (der_y, der_v and every Real output) with central differences of the values the FMU
gives at the perturbed point (fmi2SetContinuousStates, fmi2SetReal), and restores the state. The
differences use steps of 1e-4 and 5e-5 of the problem's scales (the FMU's nominals), extrapolated
(Richardson), at points where the laws are smooth within that step (a point where the one-sided
differences disagree, next to the kink of the Johnson virgin curve at delta_Y say, is passed over for
a later one); a pair agrees when
|J - J_fd| <= 1e-5 (|J| + |J_fd|) + 1e-9 * (the unknown's scale / the known's scale), the unknown's scale
its value (W_plastic's at least F delta, the size of the works it is the difference of). The same check
is repeated 1e-6 s later (fmi2SetTime forward), where the mean force covers a step of its own.
Every nonzero partial must be declared in ModelStructure.

With the upper stop (upper_stop = true) the same check runs through the independent importer
(me_importer.Importer), FMI 2.0 and 3.0, at the first completed step in each pair of modes (mode,
mode_upper) a run reaches: the mass falls up onto the upper surface (g = -9.81: the upper contact
elastic, plastic and unloading with Johnson and Thornton, elastic with damped Hertz, also with its
platform rate from vC_in), sticks to it, or the paper's Johnson scene meets an upper surface 4 um
above the start (the lower contact in its modes while the upper one is free, and the upper contact
hit). There the unknowns cover both contacts (W_dissipated, E_contact, k_contact, F_mean and der_v
both, F, F_peak and the memory outputs the lower contact's, F_upper and delta_upper the upper one's).
"""
import ctypes

import numpy as np
import pytest
from fmpy import read_model_description

from me_importer import Importer
from vibroimpact import fmu as _fmu
from vibroimpact.reference import model as M
from vibroimpact.reference.scenarios import SCENARIOS
from vibroimpact.me import MeInstance

KNOWNS = ["y", "v", "W_damping", "yC_in", "F_ext"]
STATES = ["y", "v", "W_damping"]
FD_REL = 1e-4
TOL_REL, TOL_ABS = 1e-5, 1e-9
KINK_REL = 1e-2
# scenario -> modes it reaches within 0.02 s (all five modes and the four law variants are covered)
CASES = {"fig5c": [0, 1], "fig4b": [0, 1, 2, 3], "stick": [2, 3, 4], "continuous": [0, 1, 2, 3], "fig4c": [0, 1, 2],
         "fig6a": [0, 1, 2], "damped": [0, 1], "linear": [0, 1]}
# cases that are no scenario of the table: the damped laws (their force and damping power depend on v)
EXTRA = {"damped": dict(contact_model=4, e_restitution=0.6, Y=6e8, a=1e-4, f=560.0),
         "linear": dict(contact_model=5, e_restitution=0.5, Y=6e8, a=3e-5, f=560.0)}


def unknowns(md):
    der = [u.variable.name for u in md.derivatives]  # the states' (FMI 3.0 also has the inputs' der(yC_in), ...)
    outs = [v.name for v in md.modelVariables if v.causality == "output" and v.type in ("Real", "Float64")]
    return der + outs


def declared(md):
    deps = {}
    for u in md.outputs + md.derivatives:
        deps[u.variable.name] = {d.name for d in u.dependencies}
    return deps


class Probe:
    """An FMI 2.0 Model Exchange instance (fmpy's FMU2Model of a MeInstance) as check_point sees it."""

    def __init__(self, inst):
        self.inst, self.fmu, self.vr = inst, inst.model, inst.vr

    def get_state(self):
        return self.fmu.getFMUstate()

    def set_state(self, state):
        self.fmu.setFMUstate(state)

    def free_state(self, state):
        self.fmu.freeFMUstate(state)

    def jacobian(self, names, known):
        return np.array(self.fmu.getDirectionalDerivative([self.vr[n] for n in names], [self.vr[known]], [1.0]))

    def real(self, name):
        return self.fmu.getReal([self.vr[name]])[0]

    def mode(self):
        return self.fmu.getInteger([self.vr["mode"]])[0]

    def states(self):
        x = (ctypes.c_double * len(STATES))()
        self.fmu.getContinuousStates(x, len(STATES))
        return list(x)

    def set_states(self, x):
        self.fmu.setContinuousStates((ctypes.c_double * len(STATES))(*x), len(STATES))

    def values(self, names):
        return np.array(self.fmu.getReal([self.vr[n] for n in names]))

    def nominals(self):
        x = (ctypes.c_double * len(STATES))()
        self.fmu.getNominalsOfContinuousStates(x, len(STATES))
        return list(x)

    def at(self, known, value, names):
        """The unknowns with one known changed (restored afterwards by the caller's FMU state)."""
        if known in STATES:
            x = self.states()
            x[STATES.index(known)] = value
            self.set_states(x)
        else:
            self.fmu.setReal([self.vr[known]], [value])
        return self.values(names)


def check_point(probe, md, names, deps, record, knowns=KNOWNS):
    """Compare at the current point; False (nothing asserted) where a force law has a kink within the
    difference step (the one-sided differences disagree by more than KINK_REL)."""
    state = probe.get_state()
    L, V, E = probe.nominals()
    x = probe.states()
    base = {"y": x[0], "v": x[1], "W_damping": x[2], **{k: probe.real(k) for k in ("yC_in", "F_ext", "vC_in")}}
    scale = {"y": L, "v": V, "W_damping": E, "yC_in": L, "F_ext": 1e4, "vC_in": V}
    f0 = probe.values(names)
    out_scale = np.maximum(np.abs(f0), 1e-30)
    # W_plastic is the loading work less the returned energy, each about F delta: it is exact to their
    # rounding only (continuous unloading returns the whole loading work below 4.61 delta_Y: 0 to rounding)
    work_scale = max(abs(f0[names.index(F)] * f0[names.index(d)]) for F, d in (("F", "delta"), ("F_upper", "delta_upper")))
    for work in ("W_plastic", "W_dissipated"):  # W_dissipated holds W_plastic (of both contacts)
        i = names.index(work)
        out_scale[i] = max(out_scale[i], work_scale)
    mode = probe.mode()
    checks = []
    for known in knowns:
        J = probe.jacobian(names, known)
        central = []
        for h in (FD_REL * scale[known], 0.5 * FD_REL * scale[known]):
            fp = probe.at(known, base[known] + h, names)
            probe.set_state(state)
            fm = probe.at(known, base[known] - h, names)
            probe.set_state(state)
            fwd, bwd = (fp - f0) / h, (f0 - fm) / h
            if np.any(np.abs(fwd - bwd) > KINK_REL * (np.abs(fwd) + np.abs(bwd)) + TOL_ABS * out_scale / scale[known]):
                probe.free_state(state)
                return False
            central.append((fp - fm) / (2 * h))
        # Richardson's extrapolation of the two central differences: error O(h^4), so that a
        # partial that varies fast (a Hertz contact's curvature near its onset) is still resolved
        checks.append((known, J, (4.0 * central[1] - central[0]) / 3.0))
    for known, J, fd in checks:
        for i, n in enumerate(names):
            tol = TOL_REL * (abs(J[i]) + abs(fd[i])) + TOL_ABS * max(out_scale[i], abs(f0[i])) / scale[known]
            assert abs(J[i] - fd[i]) <= tol, (mode, n, known, J[i], fd[i])
            if J[i] != 0.0:
                assert known in deps[n], f"d{n}/d{known} = {J[i]} in mode {mode} is not declared"
                record.add((n, known))
    probe.free_state(state)
    return True


@pytest.mark.parametrize("name", CASES)
def test_jacobian_matches_finite_differences_in_every_mode(name, fmu_path, unzipdir, model_description):
    md = model_description
    names, deps = unknowns(md), declared(md)
    inst = MeInstance(fmu_path, unzipdir, md)
    fmu = inst.instantiate(categories=())
    probe = Probe(inst)
    seen, record = set(), set()
    from fmpy import simulate_fmu

    def step_finished(time, recorder):
        mode = fmu.getInteger([inst.vr["mode"]])[0]
        if mode in seen or time <= 0.0 or not check_point(probe, md, names, deps, record):
            return True
        state = fmu.getFMUstate()
        fmu.setTime(time + 1e-6)  # a mean force over a step of its own
        smooth = check_point(probe, md, names, deps, record)
        fmu.setFMUstate(state)
        fmu.freeFMUstate(state)
        if smooth:
            seen.add(mode)
        return len(seen) < len(CASES[name])

    simulate_fmu(str(fmu_path), fmi_type="ModelExchange", solver="CVode", stop_time=0.02, relative_tolerance=1e-9,
                 start_values=EXTRA.get(name) or SCENARIOS[name].full, output_interval=1e-5, fmu_instance=fmu,
                 model_description=md, step_finished=step_finished, output=["y"])
    fmu.freeInstance()
    assert not inst.errors(), inst.errors()
    assert seen == set(CASES[name]), seen
    assert ("der_v", "y") in record and ("der_y", "v") in record and ("F", "yC_in") in record
    if name in EXTRA:  # the damping's power and the energies
        assert {("der_W_damping", "v"), ("der_W_damping", "y"), ("W_dissipated", "W_damping"), ("E_contact", "y")} <= record


class ImporterProbe(Probe):
    """An FMI 2.0 or 3.0 Model Exchange instance driven by me_importer.Importer, as check_point sees it."""

    def __init__(self, imp):
        self.imp, self.fmu, self.vr = imp, imp.model, imp.vr
        self.fmi3 = imp.fmi3

    def get_state(self):
        return self.fmu.getFMUState() if self.fmi3 else self.fmu.getFMUstate()

    def set_state(self, state):
        (self.fmu.setFMUState if self.fmi3 else self.fmu.setFMUstate)(state)

    def free_state(self, state):
        (self.fmu.freeFMUState if self.fmi3 else self.fmu.freeFMUstate)(state)

    def values(self, names):
        return np.array((self.fmu.getFloat64 if self.fmi3 else self.fmu.getReal)([self.vr[n] for n in names]))

    def real(self, name):
        return self.imp.real(name)

    def mode(self):
        return (self.imp.integer("mode"), self.imp.integer("mode_upper"))

    def states(self):
        return list(self.imp._states())

    def nominals(self):
        return list(self.imp._nominals())

    def at(self, known, value, names):
        if known in STATES:
            x = self.states()
            x[STATES.index(known)] = value
            self.fmu.setContinuousStates((ctypes.c_double * len(x))(*x), len(x))
        else:
            self.imp._set(known, value)
        return self.values(names)


MIRROR = dict(m=0.03288, P=0.0, R1=0.01, R2=0.0, Y=1e9, a=0.0, gap=0.005, g=-9.81)  # falls up 5 mm: 0.31 m/s
PLASTIC = {(0, 0), (0, 1), (0, 2), (0, 3)}
# case -> (parameters with the upper stop, seconds to run, (mode, mode_upper) pairs to reach)
TWO_SIDED = {
    "johnson": (dict(MIRROR, contact_model=M.JOHNSON), 0.045, PLASTIC),
    "thornton": (dict(MIRROR, contact_model=M.THORNTON), 0.045, PLASTIC),
    "hertz_damped": (dict(MIRROR, contact_model=M.HERTZ_DAMPED, e_restitution=0.6), 0.045, {(0, 0), (0, 1)}),
    "hertz_damped_vC_in": (dict(MIRROR, contact_model=M.HERTZ_DAMPED, e_restitution=0.6, velocity_input=True), 0.045,
                           {(0, 0), (0, 1)}),
    "stick": (dict(P=-40000.0, g=-9.81, a=-3e-4, f=100.0, Y=2e8, gap=1e-12), 0.012, {(0, 4)}),
    "paper": (dict(a=2e-5, f=560.0, gap=4e-6), 0.01, {(0, 0), (0, 1), (1, 0), (2, 0), (3, 0)}),
}


@pytest.mark.timeout(600)
@pytest.mark.parametrize("fmi", ["2.0", "3.0"])
@pytest.mark.parametrize("name", TWO_SIDED)
def test_jacobian_with_the_upper_stop_matches_finite_differences(name, fmi):
    """upper_stop = true: the directional derivatives of every unknown with respect to the states and
    inputs are central differences of the outputs at the first completed step in each pair of modes
    (mode, mode_upper) the run reaches (and 1e-6 s later), through the independent importer."""
    path = str(_fmu.fmu_path() if fmi == "2.0" else _fmu.fmu3_path())
    params, t_end, modes = TWO_SIDED[name]
    md = read_model_description(path)
    names, deps = unknowns(md), declared(md)
    knowns = KNOWNS + (["vC_in"] if params.get("velocity_input") else [])
    imp = Importer(path, dict(params, init=2, upper_stop=True, rtol=1e-10), rtol=1e-10, max_step=1e-5)
    probe = ImporterProbe(imp)
    seen, record = set(), set()

    def step_finished(i, t):
        pair = probe.mode()
        if pair in seen or t <= 0.0 or not check_point(probe, md, names, deps, record, knowns):
            return
        state = probe.get_state()
        i.model.setTime(t + 1e-6)  # a mean force over a step of its own
        smooth = check_point(probe, md, names, deps, record, knowns)
        probe.set_state(state)
        probe.free_state(state)
        if smooth:
            seen.add(pair)
    imp.run(t_end, step_finished)
    assert seen >= modes, seen
    if any(upper in (1, 2) for _, upper in modes):   # the upper contact's rows were nonzero
        assert {("F_upper", "y"), ("E_contact", "y"), ("k_contact", "y")} <= record, record
    if any(upper == 2 for _, upper in modes):
        assert ("W_dissipated", "y") in record and ("W_plastic", "y") not in record


def test_directional_derivative_is_linear_in_the_seeds(fmu_path, unzipdir, model_description):
    """Several knowns at once give the seeded sum of the single partials, whatever the seeds (a
    small one, 1e-3, and 0 among them): J dknown, not a sample of the seeds; the result overwrites
    what the importer's array held."""
    from fmpy.fmi2 import FMU2Model

    md = model_description
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Model(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.modelExchange.modelIdentifier,
                    instanceName="seeds")
    fmu.instantiate()
    try:
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        unknown = [vr["der_y"], vr["der_v"]]
        knowns = ["v", "y", "F_ext"]
        single = {k: np.array(fmu.getDirectionalDerivative(unknown, [vr[k]], [1.0])) for k in knowns}
        assert single["v"][0] == 1.0 and single["F_ext"][1] != 0.0  # der_y = v; F_ext drives der_v
        for seeds in ([1e-3, 0.0, 2.5], [0.0, 1e-3, 1e-3], [-1e-3, 4.0, 0.0]):
            got = np.array(fmu.getDirectionalDerivative(unknown, [vr[k] for k in knowns], seeds))
            want = sum(s * single[k] for s, k in zip(seeds, knowns))
            assert got == pytest.approx(want, rel=1e-12, abs=0.0), (seeds, got, want)
        # the importer's array may hold anything before the call: it is written, not added to
        n = len(unknown)
        out = (ctypes.c_double * n)(*([7.0] * n))
        fmu.fmi2GetDirectionalDerivative(fmu.component, (ctypes.c_uint * n)(*unknown), n, (ctypes.c_uint * 1)(vr["v"]), 1,
                                         (ctypes.c_double * 1)(1.0), out)
        assert list(out) == list(single["v"]), (list(out), single["v"])
    finally:
        fmu.terminate()
        fmu.freeInstance()
