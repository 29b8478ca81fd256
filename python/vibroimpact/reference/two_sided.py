"""The two-sided contact in the independent reference: a mass between the platform's surface (the
lower contact) and a second surface at yC + gap that moves with it (the upper contact: a cavity's lid,
the other flank of a clearance), the same law and material on both sides.

Each contact is the one-sided model's contact (model.Model) in its own coordinates. The lower one is
the one-sided model itself: indentation delta_l = yC - y, rate yC' - v. The upper one is the same
model mirrored: its indentation is delta_u = y - (yC + gap), so that with the coordinates -y for the
mass and -(yC + gap) for its surface it is a lower contact again, of a platform -(yC_in + gap) +
(-a)(cos(2 pi f t) - 1) under the load -W. The mass feels the difference of the two forces,

    y' = v,    m v' = F_lower - F_upper - W,    W = P + m g - F_ext,

and the two cannot both overlap (delta_l > 0 and delta_u > 0 would need yC > y > yC + gap), so that
each contact's modes, surfaces, snapping and resolution are those of the one-sided model, with the
other contact's force zero whenever its own is not.

The integrated state is that of one side, its frame: [delta, v, w] in that side's coordinates (the
side of the last event), so that an event puts the indentation exactly on a surface as in the
one-sided model; the other side's indentation is delta_other = -gap - delta, its velocity -v.

simulate(params, t_end) takes the parameters of model.DEFAULTS and `gap` [m] (> 0) and returns a
TwoSidedResult sampled at t_eval (default: every solver step and event).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from . import model as one

LOWER, UPPER = 0, 1


def contacts(params: dict, gap: float):
    """(lower, upper) one-sided models of the two contacts (the upper one mirrored)."""
    if not gap > 0.0:
        raise ValueError(f"gap = {gap} m: the clearance must be > 0")
    p = one.full_params(params)
    mirrored = dict(p, a=-p["a"], yC_in=-(p["yC_in"] + gap), P=-p["P"], g=-p["g"], F_ext=-p["F_ext"])
    return one.Model(p), one.Model(mirrored)


class _Pair:
    """The two contacts' models and the clearance between them."""

    def __init__(self, params, gap):
        self.models, self.gap = contacts(params, gap), float(gap)

    def other(self, delta, v):
        """The other side's (delta, v) from one side's (in its own coordinates)."""
        return -self.gap - delta, -v

    def local(self, frame, side, Y):
        """Side `side`'s state [delta, v, 0] from the state Y of frame `frame`."""
        if side == frame:
            return np.array([Y[0], Y[1], 0.0])
        d, v = self.other(Y[0], Y[1])
        return np.array([d, v, 0.0])

    def y_lower(self, frame, t, Y):
        """(y, v, delta_lower, delta_upper) of the mass from frame `frame`'s state."""
        dl, vl = self.local(frame, LOWER, Y)[:2]
        return self.models[LOWER].yC(t) - dl, vl, dl, -self.gap - dl

    def resolve(self, frame, t, Y, mems):
        return [m.resolve(t, *self.local(frame, s, Y)[:2], mems[s]) for s, m in enumerate(self.models)]


def _rhs(pair, frame, modes, mems):
    """f(t, [delta, v, w]) in frame `frame`: w the work of the frame's platform surface on the mass [J]."""
    own, oth = pair.models[frame], pair.models[1 - frame]
    F_own, F_oth = own.force_fn(modes[frame], mems[frame]), oth.force_fn(modes[1 - frame], mems[1 - frame])
    if modes[1 - frame] == one.STICK:
        raise RuntimeError("a stick on the side away from the last event")
    m, W, yC1, yC2 = own.m, own.W, own.yC1, own.yC2
    if modes[frame] == one.STICK:  # sliding on delta = delta_c: the mass moves with the platform
        return lambda t, Y: (0.0, yC2(t), own.F_hold(t) * yC1(t))
    gap = pair.gap

    def f(t, Y):
        u = yC1(t)
        fo = max(F_own(t, Y[0], Y[1]), 0.0)
        fx = max(F_oth(t, -gap - Y[0], -Y[1]), 0.0)
        return (u - Y[1], (fo - fx - W) / m, (fo - fx) * u)
    return f


def _events(pair, frame, modes, mems, t0, Y0):
    """The terminal events of both contacts' surfaces in the frame's state, and their (side, kind)."""
    events, names = [], []
    for side, model in enumerate(pair.models):
        for g, direction, kind in model.surfaces(modes[side], mems[side]):
            def g2(t, Y, g=g, side=side):
                return g(t, pair.local(frame, side, Y))
            events.append(one._wrap_event(g2, direction, t0, Y0))
            names.append((side, kind))
    return events, names


def _first_step(pair, frame, modes, mems, t0, Y0, atol):
    """The first step at a contact onset: where the Hertz-type force's non-smooth start stays below
    atol (model._singular_step), on the side that has just touched; None elsewhere."""
    h = None
    for side, model in enumerate(pair.models):
        d, v, _ = pair.local(frame, side, Y0)
        rate = model.yC1(t0) - v
        law = one._hertz_stiffness(model, modes[side], mems[side], rate)
        if law is not None and d == model.contact_surface(mems[side]) and rate > 0.0:
            step = one._singular_step(model, law, rate, atol)
            h = step if h is None else min(h, step)
    return h


@dataclass
class TwoSidedResult:
    """The two-sided run sampled at t: the mass, both contacts and the events."""
    t: np.ndarray
    y: np.ndarray
    v: np.ndarray
    yC: np.ndarray
    F_lower: np.ndarray
    F_upper: np.ndarray
    delta_lower: np.ndarray
    delta_upper: np.ndarray
    mode_lower: np.ndarray
    mode_upper: np.ndarray
    events: list = field(default_factory=list)   # (t, side, kind, mode before, mode after, v after)
    impacts: tuple = ((), ())                    # onset times of each side

    def free_flight_speeds(self, side: int):
        """The mass's speed on leaving each contact of `side` [m/s], one per separation: the speed of
        the free flight that follows when there is no gravity or load."""
        return [abs(v) for t, s, kind, before, after, v in self.events
                if s == side and after == one.FREE and before != one.FREE]


def _integrate(pair, frame, modes, mems, t0, Y0, t_end, rtol, atol, max_step):
    """One stretch of fixed modes until t_end or the first event: (solution, (side, kind) or None)."""
    events, names = _events(pair, frame, modes, mems, t0, Y0)
    h1 = _first_step(pair, frame, modes, mems, t0, Y0, atol)
    if h1 is not None:
        h1 = min(h1, max_step, t_end - t0)
    sol = solve_ivp(_rhs(pair, frame, modes, mems), (t0, t_end), Y0, method="DOP853", rtol=rtol, atol=atol,
                    dense_output=True, events=events, max_step=max_step, first_step=h1)
    if sol.status < 0:
        raise RuntimeError(f"solver failed at t = {sol.t[-1]} s: {sol.message}")
    if sol.status != 1:
        return sol, None
    hits = [(te[0], i) for i, te in enumerate(sol.t_events) if len(te)]
    return sol, names[min(hits)[1]]


def _start(pair, y0, v0):
    """(frame state, memories) at t = 0: the lower frame."""
    lower = pair.models[LOWER]
    mems = [lower.initial_memory(), pair.models[UPPER].initial_memory()]
    if y0 is None:
        delta, v, mems[LOWER] = lower.initial_state()
        return np.array([delta, v, 0.0]), mems
    return np.array([lower.yC(0.0) - float(y0), float(v0), 0.0]), mems


def simulate(params: dict, gap: float, t_end: float, rtol: float = 1e-10, t_eval=None,
             y0: float | None = None, v0: float = 0.0) -> TwoSidedResult:
    """Simulate the mass between the two surfaces on [0, t_end].

    params: the one-sided model's parameters (model.DEFAULTS); gap: the clearance [m] (> 0).
    y0, v0: the mass's start [m, m/s] with virgin contacts; by default the one-sided model's start on
    the lower surface (`init`: static or touching, with its memory). A start that overlaps both
    surfaces cannot exist (gap > 0). Raises ZenoError as the one-sided model does.
    """
    pair = _Pair(params, gap)
    rtol_used, atol = one._tolerances(pair.models[LOWER], rtol, None)
    max_step = one._max_step(pair.models[LOWER])
    t, frame = 0.0, LOWER
    Y, mems = _start(pair, y0, v0)
    modes = pair.resolve(frame, t, Y, mems)
    stretches, events, impacts = [], [], ([], [])
    zeno_anchor, zeno_count = 0.0, 0
    for _ in range(10_000_000):            # bounded: every pass ends at an event or at t_end
        sol, hit = _integrate(pair, frame, modes, mems, t, Y, t_end, rtol_used, atol, max_step)
        stretches.append((t, frame, tuple(modes), tuple(mems), sol))
        if hit is None:
            break
        side, kind = hit
        t, Y = float(sol.t[-1]), pair.local(frame, side, sol.y[:, -1])
        Y[2], frame = sol.y[2, -1], side
        Y[0], Y[1], mems[side] = pair.models[side].snap(kind, t, Y[0], Y[1], mems[side])
        new = pair.resolve(frame, t, Y, mems)
        if t - zeno_anchor > one.ZENO_WINDOW:
            zeno_anchor, zeno_count = t, 0
        zeno_count += 1
        if zeno_count > one.ZENO_MAX_EVENTS:
            raise one.ZenoError(f"more than {one.ZENO_MAX_EVENTS} events within {one.ZENO_WINDOW} s at t = {t}")
        y, v, _, _ = pair.y_lower(frame, t, Y)
        for s in (LOWER, UPPER):
            if new[s] != modes[s]:
                events.append((t, s, kind, modes[s], new[s], v))
                if modes[s] == one.FREE:
                    impacts[s].append(t)
        modes = new
        if t >= t_end:
            break
    return _sample(pair, stretches, events, impacts, t_eval)


def _sample(pair, stretches, events, impacts, t_eval) -> TwoSidedResult:
    """The outputs at t_eval from the stretches' dense outputs (after an event at t: the state after it)."""
    if t_eval is None:
        t_eval = np.unique(np.concatenate([s[4].t for s in stretches]))
    t_eval = np.asarray(t_eval, float)
    index = np.searchsorted(np.array([s[0] for s in stretches]), t_eval, side="right") - 1
    n = len(t_eval)
    out = {k: np.zeros(n) for k in ("y", "v", "F_lower", "F_upper", "delta_lower", "delta_upper")}
    mode_l, mode_u = np.zeros(n, int), np.zeros(n, int)
    for i in np.unique(index):
        t0, frame, modes, mems, sol = stretches[i]
        for j in np.nonzero(index == i)[0]:
            tj = t_eval[j]
            Y = sol.y[:, 0] if tj == t0 else sol.sol(tj)
            y, v, dl, du = pair.y_lower(frame, tj, Y)
            out["y"][j], out["v"][j], out["delta_lower"][j], out["delta_upper"][j] = y, v, dl, du
            out["F_lower"][j] = max(pair.models[LOWER].force_fn(modes[0], mems[0])(tj, dl, v), 0.0)
            out["F_upper"][j] = max(pair.models[UPPER].force_fn(modes[1], mems[1])(tj, du, -v), 0.0)
            mode_l[j], mode_u[j] = modes
    return TwoSidedResult(t=t_eval, yC=pair.models[LOWER].yC(t_eval), mode_lower=mode_l, mode_upper=mode_u,
                          events=events, impacts=(tuple(impacts[0]), tuple(impacts[1])), **out)
