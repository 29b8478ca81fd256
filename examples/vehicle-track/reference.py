"""Monolithic reference of the vehicle-track example: one SciPy ODE for the whole coupled system,
written from the equations (doc/model.md, sections 1, 2 and 6), independently of the C code.

Vertical axis up. Wheel (mass m_w, the contact FMU's mass), sprung mass m_b on the primary
suspension (k_s, c_s), rail m_r on the pad (k_p, c_p), sleeper m_sl on the ballast (k_b, c_b):

    m_w y''    = F - m_w g + F_s                      F_s = -m_b g + k_s (z_b - y) + c_s (v_b - v)
    m_b z_b''  = -k_s (z_b - y) - c_s (v_b - v)        (z_b = y when the spring carries m_b g)
    m_r z_r''  = -F - k_p (z_r - z_sl) - c_p (v_r - v_sl)
    m_sl z_sl'' = k_p (z_r - z_sl) + c_p (v_r - v_sl) - k_b z_sl - c_b v_sl

with the Hertz contact force F = K delta^1.5 for delta > 0 and 0 otherwise,
K = 4/3 E* sqrt(R*), delta = yC - y, yC = z_r + yb(x0 + V t). yb is the rigid rolling constraint
of a wheel of radius R1 on the profile h(x), linear between its samples:

    yb(x) = max over s, |s - x| <= R1, of [h(s) + sqrt(R1^2 - (x - s)^2)] - R1,

computed exactly: the maximum is reached at a vertex (a circle about the vertex) or where the
wheel touches a segment (the segment shifted along its normal by R1).

Contact loss and contact onset (delta crossing 0) are located as events and the integration
restarts there. Besides the 8 states the integration carries the impulse J = int F dt (so the
mean force over any interval is exact), the dissipated work D and the work of the roughness
W_r = int F yb' dt, which close the energy balance

    E_kin + E_springs + (m_w + m_b) g y + 2/5 K delta^2.5 + D - W_r = const.

The start is static: every body at rest under the weight (m_w + m_b) g on a flat rail.
"""
import argparse
import math

import numpy as np
from scipy.integrate import DOP853, OdeSolution
from scipy.optimize import brentq

import parameters

E_STAR_OF = lambda E1, nu1, E2, nu2: 1.0 / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)  # noqa: E731

# state indices
YW, VW, ZB, VB, ZR, VR, ZS, VS, J, D, WR = range(11)
N_STATE = 11


class Profile:
    """The rigid rolling constraint yb(x) of a wheel of radius R on a piecewise-linear profile."""

    def __init__(self, x, h, R):
        self.x, self.h, self.R = np.asarray(x, float), np.asarray(h, float), float(R)
        if np.any(np.diff(self.x) <= 0):
            raise ValueError("profile x must increase")
        self.slope = np.diff(self.h) / np.diff(self.x)
        self.sec = np.sqrt(1.0 + self.slope ** 2)
        # Window: a vertex farther than w from x cannot carry the wheel, because its circle is
        # below the lowest point the nearest vertex guarantees (exact bound, not an approximation).
        dh = self.h.max() - self.h.min()
        dx = np.max(np.diff(self.x))
        e = R - np.sqrt(max(R * R - dx * dx, 0.0))
        self.w = np.sqrt(max(R * R - (R - dh - e) ** 2, 0.0)) + 2 * dx

    @classmethod
    def from_file(cls, path, R):
        x, h = np.loadtxt(path, unpack=True)
        return cls(x, h, R)

    def __call__(self, x):
        """yb(x) [m] and dyb/dx [1]."""
        val, der, _ = self.evaluate(np.array([x], float))
        return val[0], der[0]

    def evaluate(self, xs):
        """yb, dyb/dx and what carries the wheel (2 j: vertex j; 2 j + 1: segment j) at each x."""
        xs = np.asarray(xs, float)
        if xs.min() - self.R < self.x[0] or xs.max() + self.R > self.x[-1]:
            raise ValueError(f"x in [{xs.min()}, {xs.max()}] m: the wheel leaves the profile "
                             f"[{self.x[0]}, {self.x[-1]}] m")
        n = len(self.x)
        nw = int(np.ceil(2 * self.w / np.min(np.diff(self.x)))) + 4
        i0 = np.clip(np.searchsorted(self.x, xs - self.w) - 2, 0, n - 1)
        iv = np.minimum(i0[:, None] + np.arange(nw)[None, :], n - 1)       # vertices
        d = xs[:, None] - self.x[iv]
        inside = np.abs(d) < self.R
        root = np.sqrt(np.where(inside, self.R ** 2 - d ** 2, 1.0))
        cv = np.where(inside, self.h[iv] + root - self.R, -np.inf)
        best = np.argmax(cv, axis=1)
        rows = np.arange(len(xs))
        val, der = cv[rows, best], -d[rows, best] / root[rows, best]
        which = 2 * iv[rows, best]
        js = np.minimum(iv, n - 2)                                           # segments
        s, sec = self.slope[js], self.sec[js]
        xi = xs[:, None] + self.R * s / sec
        ok = (xi >= self.x[js]) & (xi <= self.x[js + 1])
        cs = np.where(ok, self.h[js] + s * (xs[:, None] - self.x[js]) + self.R * (sec - 1.0), -np.inf)
        k = np.argmax(cs, axis=1)
        seg = cs[rows, k] > val
        val = np.where(seg, cs[rows, k], val)
        der = np.where(seg, s[rows, k], der)
        which = np.where(seg, 2 * js[rows, k] + 1, which)
        return val, der, which

    def carriers(self, xa, xb, per_sample=8, chunk=20000, max_levels=64):
        """The exact piecewise form of yb on [xa, xb]: the start of each interval and what carries
        the wheel on it (2 j: vertex j, a circle; 2 j + 1: segment j, a line). Changes are
        bracketed on a grid of per_sample points per profile interval; every bracket whose ends
        differ is bisected to machine precision, and the rest of the bracket is searched again,
        so that several changes inside one grid cell are all found."""
        n = int(np.ceil((xb - xa) / (np.min(np.diff(self.x)) / per_sample))) + 1
        grid = np.linspace(xa, xb, n)
        ids = np.concatenate([self.evaluate(grid[i:i + chunk])[2] for i in range(0, n, chunk)])
        cell = np.flatnonzero(ids[1:] != ids[:-1])
        lo, hi, a, b = grid[cell], grid[cell + 1], ids[cell], ids[cell + 1]
        starts, which = [np.array([xa])], [ids[:1]]
        for _ in range(max_levels):  # bounded: each level resolves one change per open bracket
            if len(lo) == 0:
                break
            l, r = lo.copy(), hi.copy()
            for _ in range(60):  # bisection of all brackets at once
                mid = 0.5 * (l + r)
                left = self.evaluate(mid)[2] == a
                l, r = np.where(left, mid, l), np.where(left, r, mid)
            m = self.evaluate(r)[2]
            starts.append(r)
            which.append(m)
            more = m != b  # another change between r and the bracket's end
            lo, hi, a, b = r[more], hi[more], m[more], b[more]
        else:
            raise RuntimeError("profile: too many carrier changes inside one grid cell")
        starts, which = np.concatenate(starts), np.concatenate(which)
        order = np.argsort(starts, kind="stable")
        return starts[order], which[order]

    def at(self, x, which):
        """yb and dyb/dx at x on carrier `which` (scalar, plain floats: fast)."""
        j = which >> 1
        if which & 1:
            s = self.slope[j]
            return self.h[j] + s * (x - self.x[j]) + self.R * (self.sec[j] - 1.0), s
        d = x - self.x[j]
        root = math.sqrt(self.R * self.R - d * d)
        return self.h[j] + root - self.R, -d / root


class System:
    """The coupled equations. With a profile, yb(t) follows its exact piecewise form along the
    path x0 + V t up to t_end (Profile.carriers)."""

    def __init__(self, track=None, vehicle=None, wheel=None, profile=None, t_end=parameters.STOP_TIME,
                 excitation=None):
        self.tr = dict(parameters.TRACK, **(track or {}))
        self.ve = dict(parameters.VEHICLE, **(vehicle or {}))
        self.wh = dict(parameters.WHEEL, **(wheel or {}))
        w = self.wh
        Es = E_STAR_OF(w["E1"], w["nu1"], w["E2"], w["nu2"])
        Rs = 1.0 / (1.0 / w["R1"] + (1.0 / w["R2"] if w["R2"] > 0 else 0.0))
        self.K = 4.0 / 3.0 * Es * np.sqrt(Rs)
        self.W = (w["m"] + self.ve["m_body"]) * w["g"] + w["P"]  # static wheel load [N]
        self.profile = profile
        self.a, self.f = excitation or (0.0, 0.0)  # the contact FMU's internal harmonic a (cos 2 pi f t - 1)
        if profile is not None:
            starts, self.which = profile.carriers(w["x0"], w["x0"] + w["V"] * t_end)
            self.t_pieces = (starts - w["x0"]) / w["V"]
            self.t_pieces[0] = 0.0
        else:
            self.t_pieces, self.which = np.array([0.0]), None

    def yb(self, t, piece=None):
        """The platform motion added to the rail's, yC - z_r [m], and its time derivative [m/s] at t:
        the harmonic term and yb (on the given piece, else the one at t)."""
        wt = 2.0 * math.pi * self.f * t
        harm, dharm = self.a * (math.cos(wt) - 1.0), -self.a * 2.0 * math.pi * self.f * math.sin(wt)
        if self.profile is None:
            return harm, dharm
        w = self.wh
        if piece is None:
            piece = max(int(np.searchsorted(self.t_pieces, t, side="right")) - 1, 0)
        val, slope = self.profile.at(w["x0"] + w["V"] * t, int(self.which[piece]))
        return val + harm, slope * w["V"] + dharm

    def force(self, delta):
        return self.K * delta ** 1.5 if delta > 0.0 else 0.0

    def static_state(self):
        """Every body at rest under the static wheel load W."""
        x = np.zeros(N_STATE)
        x[ZS] = -self.W / self.tr["k_ballast"]
        x[ZR] = x[ZS] - self.W / self.tr["k_pad"]
        x[YW] = x[ZR] + self.yb(0.0)[0] - (self.W / self.K) ** (2.0 / 3.0)
        x[ZB] = x[YW]
        return x

    def rhs(self, t, x, piece=None):
        tr, ve, w = self.tr, self.ve, self.wh
        yb, dyb = self.yb(t, piece)
        yw, vw, zb, vb, zr, vr, zs, vs = x[:8]
        F = self.force(zr + yb - yw)
        Fs = -ve["m_body"] * w["g"] + ve["k_susp"] * (zb - yw) + ve["c_susp"] * (vb - vw)
        Fp = tr["k_pad"] * (zr - zs) + tr["c_pad"] * (vr - vs)
        return np.array([
            vw, (F - w["P"] - w["m"] * w["g"] + Fs) / w["m"],
            vb, -(Fs + ve["m_body"] * w["g"]) / ve["m_body"],
            vr, (-F - Fp) / tr["m_rail"],
            vs, (Fp - tr["k_ballast"] * zs - tr["c_ballast"] * vs) / tr["m_sleeper"],
            F,
            ve["c_susp"] * (vb - vw) ** 2 + tr["c_pad"] * (vr - vs) ** 2 + tr["c_ballast"] * vs ** 2,
            F * dyb])

    def delta(self, t, x, piece=None):
        return x[ZR] + self.yb(t, piece)[0] - x[YW]

    def energy(self, t, x):
        """Stored energy: kinetic, springs, gravity (with the suspension preload), Hertz."""
        tr, ve, w = self.tr, self.ve, self.wh
        delta = max(self.delta(t, x), 0.0)
        return (0.5 * w["m"] * x[VW] ** 2 + 0.5 * ve["m_body"] * x[VB] ** 2 + 0.5 * tr["m_rail"] * x[VR] ** 2
                + 0.5 * tr["m_sleeper"] * x[VS] ** 2 + 0.5 * ve["k_susp"] * (x[ZB] - x[YW]) ** 2
                + 0.5 * tr["k_pad"] * (x[ZR] - x[ZS]) ** 2 + 0.5 * tr["k_ballast"] * x[ZS] ** 2
                + (w["m"] * w["g"] + ve["m_body"] * w["g"] + w["P"]) * x[YW] + 0.4 * self.K * delta ** 2.5)


class Solution:
    """Dense output of a reference run (scipy's OdeSolution over every step) and its events."""

    def __init__(self, system, ts, interpolants, events):
        self.system, self.events = system, events
        self.sol = OdeSolution(ts, interpolants)

    def state(self, t):
        return self.sol(np.atleast_1d(np.asarray(t, float)))

    def force(self, t):
        t = np.atleast_1d(t)
        x = self.state(t)
        return np.array([self.system.force(self.system.delta(tt, x[:, k])) for k, tt in enumerate(t)])

    def mean_force(self, t_grid):
        """Force averaged over each interval of t_grid (exact: from the impulse)."""
        return np.diff(self.state(t_grid)[J]) / np.diff(t_grid)

    def energy_residual(self, t):
        t = np.atleast_1d(t)
        x = self.state(t)
        E0 = self.system.energy(0.0, self.state(0.0)[:, 0])
        return np.array([self.system.energy(tt, x[:, k]) + x[D, k] - x[WR, k] - E0 for k, tt in enumerate(t)])


SCALE = np.array([1e-6, 1e-3, 1e-6, 1e-3, 1e-6, 1e-3, 1e-6, 1e-3, 1e-3, 1e-3, 1e-3])  # absolute tolerance / rtol


def simulate(system, t_end, rtol=1e-8, max_steps=10 ** 7):
    """Integrate from the static start to t_end with DOP853. Every change of what carries the
    wheel ends a piece (there yb' jumps or yb'' jumps), and the integrator restarts there, so
    each piece is smooth. Contact loss and onset (delta through 0) are located on the dense
    output (brentq) and the integrator restarts there too, on the side the event leads to: at the
    located time delta is zero to rounding and may still carry the old sign, which must not count
    as the same crossing again."""
    x, t = system.static_state(), 0.0
    bounds = np.append(system.t_pieces[1:], t_end)
    bounds = bounds[bounds <= t_end]
    ts, interps, events = [t], [], []
    piece, h, side = 0, None, None  # side: the sign of delta just after the last event (None: from the state)
    for _ in range(max_steps):  # bounded: every pass makes a step or starts a piece
        if t >= t_end:
            return Solution(system, ts, interps, events)
        while piece < len(bounds) - 1 and bounds[piece] <= t:
            piece += 1
        t_bound = min(bounds[piece], t_end)
        p = piece
        solver = DOP853(lambda tt, xx: system.rhs(tt, xx, p), t, x, t_bound, rtol=rtol, atol=rtol * SCALE,
                        first_step=None if h is None else min(h, t_bound - t))
        g0 = system.delta(t, x, p) if side is None else side
        side = None
        while solver.status == "running":  # bounded by max_steps through the outer loop's count
            msg = solver.step()
            if solver.status == "failed":
                raise RuntimeError(f"reference: {msg} at t = {solver.t}")
            dense = solver.dense_output()
            g1 = system.delta(solver.t, solver.y, p)
            g = lambda tt: system.delta(tt, dense(tt), p)  # noqa: E731
            # a crossing the dense output brackets (right after an event, delta at it is rounding)
            if (g0 > 0.0) != (g1 > 0.0) and g0 != 0.0 and (g(solver.t_old) > 0.0) != (g1 > 0.0):
                te = brentq(g, solver.t_old, solver.t, xtol=1e-16, rtol=1e-15)
                ts.append(te)
                interps.append(dense)
                events.append((te, "loss" if g0 > 0.0 else "onset"))
                t, x, side = te, dense(te), -1.0 if g0 > 0.0 else 1.0
                break
            ts.append(solver.t)
            interps.append(dense)
            h = solver.step_size
            g0 = g1
        else:
            t, x = solver.t, solver.y
    raise RuntimeError("reference: too many steps")


def default_system(profile_path=None, t_end=parameters.STOP_TIME, excitation=None):
    w = parameters.WHEEL
    prof = Profile.from_file(profile_path, w["R1"]) if profile_path else None
    return System(profile=prof, t_end=t_end, excitation=excitation)


def main():
    ap = argparse.ArgumentParser(description="monolithic reference run")
    ap.add_argument("--profile", help="profile file (x, h); default: generate with roughness.py")
    ap.add_argument("--t-end", type=float, default=parameters.STOP_TIME)
    ap.add_argument("--rtol", type=float, default=1e-8)
    a = ap.parse_args()
    import time

    import roughness
    path = a.profile
    if not path:
        path = "/tmp/vt_profile.txt"
        roughness.write(path, *roughness.profile(**parameters.ROUGHNESS))
    t0 = time.time()
    s = default_system(path, a.t_end)
    sol = simulate(s, a.t_end, a.rtol)
    tg = np.linspace(0, a.t_end, 1501)
    F = sol.force(tg)
    print(f"{time.time() - t0:.1f} s, {len(s.t_pieces)} pieces, {len(sol.sol.ts)} steps, events {len(sol.events)}; "
          f"F min {F.min():.0f} max {F.max():.0f} N (static {s.W:.0f}); "
          f"energy residual {np.abs(sol.energy_residual(tg)).max():.2e} J")


if __name__ == "__main__":
    main()
