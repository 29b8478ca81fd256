"""fmi2GetDirectionalDerivative against finite differences, in every mode of every law.

Each case runs a paper scenario (or a damped law under Fig. 4b's excitation) in Model Exchange
(fmpy's CVode) and, at the first completed step in each mode it reaches, with the instance in
continuous-time mode: takes an FMU state, then for every known (the states y, v, W_damping and the
inputs yC_in, F_ext) compares the FMU's partial derivatives of
every unknown (der_y, der_v and every Real output) with central differences of the values the FMU
gives at the perturbed point (fmi2SetContinuousStates, fmi2SetReal), and restores the state. The
differences use steps of 1e-4 of the problem's scales (the FMU's nominals), at points where the laws
are smooth within that step (a point where the one-sided differences disagree, next to the kink of
the Johnson virgin curve at delta_Y say, is passed over for a later one); a pair agrees when
|J - J_fd| <= 1e-5 (|J| + |J_fd|) + 1e-9 * (the unknown's scale / the known's scale), the unknown's scale
its value (W_plastic's at least F delta, the size of the works it is the difference of). The same check
is repeated 1e-6 s later (fmi2SetTime forward), where the mean force covers a step of its own.
Every nonzero partial must be declared in ModelStructure.
"""
import ctypes

import numpy as np
import pytest

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
    der = [v.name for v in md.modelVariables if v.derivative is not None]
    outs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    return der + outs


def declared(md):
    deps = {}
    for u in md.outputs + md.derivatives:
        deps[u.variable.name] = {d.name for d in u.dependencies}
    return deps


class Probe:
    def __init__(self, inst):
        self.inst, self.fmu, self.vr = inst, inst.model, inst.vr

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


def check_point(probe, md, names, deps, record):
    """Compare at the current point; False (nothing asserted) where a force law has a kink within the
    difference step (the one-sided differences disagree by more than KINK_REL)."""
    fmu = probe.fmu
    state = fmu.getFMUstate()
    L, V, E = probe.nominals()
    x = probe.states()
    base = {"y": x[0], "v": x[1], "W_damping": x[2], "yC_in": fmu.getReal([probe.vr["yC_in"]])[0],
            "F_ext": fmu.getReal([probe.vr["F_ext"]])[0]}
    scale = {"y": L, "v": V, "W_damping": E, "yC_in": L, "F_ext": 1e4}
    f0 = probe.values(names)
    out_scale = np.maximum(np.abs(f0), 1e-30)
    # W_plastic is the loading work less the returned energy, each about F delta: it is exact to their
    # rounding only (continuous unloading returns the whole loading work below 4.61 delta_Y: 0 to rounding)
    for work in ("W_plastic", "W_dissipated"):  # W_dissipated holds W_plastic
        i = names.index(work)
        out_scale[i] = max(out_scale[i], abs(f0[names.index("F")] * f0[names.index("delta")]))
    mode = fmu.getInteger([probe.vr["mode"]])[0]
    checks = []
    for known in KNOWNS:
        J = np.array(fmu.getDirectionalDerivative([probe.vr[n] for n in names], [probe.vr[known]], [1.0]))
        h = FD_REL * scale[known]
        fp = probe.at(known, base[known] + h, names)
        fmu.setFMUstate(state)
        fm = probe.at(known, base[known] - h, names)
        fmu.setFMUstate(state)
        fwd, bwd = (fp - f0) / h, (f0 - fm) / h
        if np.any(np.abs(fwd - bwd) > KINK_REL * (np.abs(fwd) + np.abs(bwd)) + TOL_ABS * out_scale / scale[known]):
            fmu.freeFMUstate(state)
            return False
        checks.append((known, J, (fp - fm) / (2 * h)))
    for known, J, fd in checks:
        for i, n in enumerate(names):
            tol = TOL_REL * (abs(J[i]) + abs(fd[i])) + TOL_ABS * max(out_scale[i], abs(f0[i])) / scale[known]
            assert abs(J[i] - fd[i]) <= tol, (mode, n, known, J[i], fd[i])
            if J[i] != 0.0:
                assert known in deps[n], f"d{n}/d{known} = {J[i]} in mode {mode} is not declared"
                record.add((n, known))
    fmu.freeFMUstate(state)
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
