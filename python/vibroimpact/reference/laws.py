"""Contact laws beyond the paper's three, written from their published equations (not from the C code):
damped Hertz (Tsuji's form with an exact restitution, and the Hunt-Crossley family), the linear
spring-dashpot, and Thornton's elastic-perfectly-plastic sphere. Each comes with the restitution of an
isolated impact, in closed form where one exists and by an independent integration (SciPy) otherwise.

Units are SI; delta is the indentation (> 0: overlap), ddelta its rate (> 0: approaching), m the mass that
hits a fixed surface, V its approach speed, K = 4/3 E* sqrt(R*) the Hertz constant.

Damped Hertz (the force never pulls: F = max(0, .)):
    tsuji           F = K delta^1.5 + alpha sqrt(m K) delta^(1/4) ddelta
    hunt_crossley   F = K delta^1.5 (1 + chi ddelta / V_i),  chi = 3 (1 - e) / 2
    lankarani       chi = 3 (1 - e^2) / 4
    flores          chi = 8 (1 - e) / (5 e)
V_i is the approach speed at the onset of the contact; a contact that starts at rest (V_i = 0) is
undamped until it ends. Scaling delta = d0 x, t = d0/V tau with d0 = (m V^2/K)^(2/5) turns each into
x'' = -x^1.5 - alpha x^(1/4) x' (tsuji) and x'' = -x^1.5 (1 + chi x') (the family, V_i = V): the
restitution depends on alpha (resp. chi) alone, at every impact speed.

Linear spring-dashpot: F = max(0, k delta + c ddelta), c = 2 zeta sqrt(m k). The force reaches 0 when the
mass's acceleration does, before delta returns to 0; with beta = asin(zeta) (zeta < 1), or
zeta = cosh(gamma) (zeta > 1), the restitution is
    e = exp(-tan(beta) (pi - 2 beta))                          underdamped
    e = exp(-2 gamma - 2 gamma exp(-gamma) / sinh(gamma))      overdamped, e(zeta = 1) = exp(-2)

Thornton (J. Appl. Mech. 64, 1997, 383): Hertz up to delta_Y, where the maximum contact pressure is the
limiting pressure p_Y; beyond, F = F_Y + pi p_Y R* (delta - delta_Y). Unloading from (delta*, F*) is Hertzian,
F = 4/3 E* sqrt(R_p) (delta - delta_p)^1.5, with the contact radius a_p^2 = (2 F* + F_Y)/(2 pi p_Y),
R_p = 4 E* a_p^3/(3 F*) and delta_p = delta* - (3 F*/(4 E* sqrt(R_p)))^(2/3). The yield speed is
1/2 m V_Y^2 = 2/5 F_Y delta_Y and, for V > V_Y with r = V_Y/V, the restitution is
    e = sqrt(6 sqrt(3)/5) sqrt(1 - r^2/6) (r / (r + 2 sqrt(6/5 - r^2/5)))^(1/4).
"""
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

# the damping_formula items of the FMU
EXACT, HUNT_CROSSLEY, LANKARANI_NIKRAVESH, FLORES = 1, 2, 3, 4
FORMULAS = {HUNT_CROSSLEY: "hunt_crossley", LANKARANI_NIKRAVESH: "lankarani_nikravesh", FLORES: "flores"}

# Tolerances of the dimensionless one-impact integrations: restitutions to about 1e-11.
IMPACT_RTOL, IMPACT_ATOL = 1e-13, 1e-15
# no impact of these laws lasts longer than this (dimensionless time): the integration's bound
IMPACT_TAU_MAX = 1e3


def chi(formula, e):
    """The damping factor chi of a published form for the target restitution e."""
    if formula == HUNT_CROSSLEY:
        return 1.5 * (1 - e)
    if formula == LANKARANI_NIKRAVESH:
        return 0.75 * (1 - e * e)
    if formula == FLORES:
        return 1.6 * (1 - e) / e
    raise ValueError(f"damping_formula {formula} has no chi")


def tsuji_impact(alpha):
    """(e, tau_contact, x_max, f_max) of the dimensionless Tsuji impact x'' = -x^1.5 - alpha x^(1/4) x'."""
    return drop(lambda x, v: x ** 1.5 + alpha * x ** 0.25 * v, 1.0, 1.0, 1.0)


def tsuji_restitution(alpha):
    return tsuji_impact(alpha)[0]


def _invert(restitution, e, xtol, rtol):
    """The damping d >= 0 with restitution(d) = e in (0, 1], restitution decreasing from 1 at d = 0: a
    bracket doubled from 1, then brentq."""
    if not 0 < e <= 1:
        raise ValueError(f"e = {e} is outside (0, 1]")
    if e == 1:
        return 0.0
    hi = 1.0
    while restitution(hi) > e:
        hi *= 2
    return brentq(lambda d: restitution(d) - e, 0.0, hi, xtol=xtol, rtol=rtol)


def tsuji_alpha(e):
    """The alpha that gives the restitution e in (0, 1] (bracketed root search on tsuji_restitution)."""
    return _invert(tsuji_restitution, e, 1e-14, 1e-13)


def tsuji_alpha_linearised(e):
    """Tsuji et al.'s linearised relation alpha = -sqrt(5) ln e / sqrt(ln^2 e + pi^2) (the one most DEM
    codes use; not exact for the Hertz contact)."""
    L = math.log(e)
    return -math.sqrt(5.0) * L / math.sqrt(L * L + math.pi ** 2)


def hc_impact(chi_):
    """(e, tau_contact, x_max, f_max) of the dimensionless impact x'' = -x^1.5 (1 + chi x')."""
    return drop(lambda x, v: x ** 1.5 * (1 + chi_ * v), 1.0, 1.0, 1.0)


def hc_restitution(formula, e):
    """The restitution that a published form really gives when asked for e."""
    return hc_impact(chi(formula, e))[0]


def hc_restitution_closed_form(chi_):
    """The family's restitution e_a from energy alone: v dv/dx = -x^1.5 (1 + chi v) separates, and over
    the round trip from x = 0 back to x = 0 it gives chi (1 + e_a) = ln((1 + chi)/(1 - chi e_a)), whatever
    the exponent (Hunt and Crossley 1975). The force stays positive (1 - chi e_a > 0): a free impact ends at
    delta = 0, the clamp never acts."""
    if chi_ == 0:
        return 1.0
    top = min(1.0, (1 - 1e-16) / chi_)
    return brentq(lambda ea: chi_ * (1 + ea) - math.log((1 + chi_) / (1 - chi_ * ea)), 0.0, top,
                  xtol=1e-15, rtol=1e-14)


def drop(force, m, V, d_scale):
    """(e, contact time, delta_max, F_max) of a mass m [kg] hitting a fixed surface at V [m/s] under the
    law force(delta, ddelta) [N] (clamped at 0 here), d_scale [m] the indentation scale for atol; it ends
    where the force falls through 0 while rebounding or delta returns to 0. With m = V = d_scale = 1 it
    is the dimensionless impact of the laws above."""
    t_scale = d_scale / V

    def rhs(_t, y):
        return [y[1], -max(force(max(y[0], 0.0), y[1]), 0.0) / m]

    def sep(_t, y):
        return force(max(y[0], 0.0), y[1]) if y[1] < 0 else 1.0
    sep.terminal, sep.direction = True, -1

    def back(_t, y):
        return y[0]
    back.terminal, back.direction = True, -1
    sol = solve_ivp(rhs, (0.0, IMPACT_TAU_MAX * t_scale), [0.0, V], method="DOP853", rtol=IMPACT_RTOL,
                    atol=[IMPACT_ATOL * d_scale, IMPACT_ATOL * V], events=(sep, back), dense_output=True)
    if sol.status != 1:
        raise RuntimeError("the impact did not end within IMPACT_TAU_MAX contact time scales")
    hits = [(ev[0], ye[0]) for ev, ye in zip(sol.t_events, sol.y_events) if len(ev)]
    t_end, y_end = min(hits, key=lambda h: h[0])
    xs, vs = sol.sol(np.linspace(0.0, t_end, 4001))
    return -y_end[1] / V, t_end, float(np.max(xs)), max(force(max(x, 0.0), v) for x, v in zip(xs, vs))


def linear_restitution(zeta):
    """Closed-form restitution of the clamped linear spring-dashpot with damping ratio zeta >= 0."""
    if zeta < 1:
        b = math.asin(zeta)
        return math.exp(-math.tan(b) * (math.pi - 2 * b))
    g = math.acosh(zeta)
    if g == 0:
        return math.exp(-2.0)
    return math.exp(-2 * g - 2 * g * math.exp(-g) / math.sinh(g))


def linear_zeta(e):
    """The damping ratio whose clamped restitution is e in (0, 1]."""
    return _invert(linear_restitution, e, 1e-15, 1e-14)


def linear_impact(zeta):
    """(e, tau_contact) of x'' = -x - 2 zeta x' (time in 1/omega) by integration, for the closed form's check."""
    e, t, _, _ = drop(lambda x, v: x + 2 * zeta * v, 1.0, 1.0, 1.0)
    return e, t


def tsuji_release(alpha):
    """(x_r, v_r) where the force of the dimensionless Tsuji impact falls to 0 while x > 0 (the release): the
    overlap and the rate there. The spring part then holds 2/5 x_r^2.5 of the impact energy 1/2."""
    def rhs(_t, y):
        return [y[1], -max(y[0] ** 1.5 + alpha * y[0] ** 0.25 * y[1], 0.0) if y[0] > 0 else 0.0]

    def release(_t, y):
        return y[0] ** 1.5 + alpha * y[0] ** 0.25 * y[1] if y[0] > 0 and y[1] < 0 else 1.0
    release.terminal, release.direction = True, -1
    sol = solve_ivp(rhs, (0.0, IMPACT_TAU_MAX), [0.0, 1.0], method="DOP853", rtol=IMPACT_RTOL, atol=IMPACT_ATOL,
                    events=release)
    if sol.status != 1:
        raise RuntimeError("the Tsuji impact did not release within IMPACT_TAU_MAX")
    x, v = sol.y_events[0][0]
    return x, v


def released_fraction(law, e):
    """The fraction of the impact energy 1/2 m V^2 the spring part of a damped law still holds when its
    force reaches 0 before the bodies part (the release), for the restitution e in (0, 1]: lost while the
    overlap falls to 0. law "exact" (Tsuji's form): 0.8 x_r^2.5 from tsuji_release; "linear": at the
    release x + 2 zeta x' = 0 with x' = -e (time in 1/omega, lengths in V/omega), so x_r = 2 zeta e and the
    spring holds x_r^2 = 4 zeta^2 e^2."""
    if e == 1.0:
        return 0.0
    if law == "exact":
        x, _ = tsuji_release(tsuji_alpha(e))
        return 0.8 * x ** 2.5
    if law == "linear":
        z = linear_zeta(e)
        return 4.0 * z * z * e * e
    raise ValueError(f"law {law!r}: 'exact' or 'linear'")


def linear_contact_time(zeta):
    """Closed-form contact time omega t_c of the clamped linear spring-dashpot."""
    if zeta < 1:
        b = math.asin(zeta)
        return (math.pi - 2 * b) / math.cos(b)
    g = math.acosh(zeta)
    return 2 * g / math.sinh(g) if g > 0 else 2.0


class Thornton:
    """Thornton's elastic-perfectly-plastic law for E* [Pa], R* [m] and the limiting (maximum) contact
    pressure p_Y [Pa]."""

    def __init__(self, E_star, R_star, p_Y):
        self.E, self.R, self.pY = E_star, R_star, p_Y
        self.K = 4 / 3 * E_star * math.sqrt(R_star)
        self.delta_Y = (math.pi * p_Y / (2 * E_star)) ** 2 * R_star
        self.F_Y = self.K * self.delta_Y ** 1.5

    def load(self, d):
        """Force on first loading."""
        if d <= 0:
            return 0.0
        if d <= self.delta_Y:
            return self.K * d ** 1.5
        return self.F_Y + math.pi * self.pY * self.R * (d - self.delta_Y)

    def unload_curve(self, d_star):
        """(R_p, delta_p, F*) after the maximum indentation d_star."""
        F = self.load(d_star)
        if d_star <= self.delta_Y:
            return self.R, 0.0, F
        a_p = math.sqrt((2 * F + self.F_Y) / (2 * math.pi * self.pY))
        R_p = 4 * self.E * a_p ** 3 / (3 * F)
        d_p = d_star - (3 * F / (4 * self.E * math.sqrt(R_p))) ** (2 / 3)
        return R_p, d_p, F

    def yield_speed(self, m):
        return math.sqrt(2 * 0.4 * self.F_Y * self.delta_Y / m)

    def impact(self, m, V):
        """(e, contact time, delta_max, F_max) of a mass m hitting at V, by integration of the law."""
        d0, t0 = self.delta_Y, self.delta_Y / V  # scales for the tolerances

        def rhs_load(_t, y):
            return [y[1], -self.load(max(y[0], 0.0)) / m]

        def turn(_t, y):
            return y[1]
        turn.terminal, turn.direction = True, -1
        s1 = solve_ivp(rhs_load, (0, 1e3 * t0), [0.0, V], method="DOP853", rtol=IMPACT_RTOL,
                       atol=[IMPACT_ATOL * d0, IMPACT_ATOL * V], events=turn)
        d_star = s1.y_events[0][0][0]
        R_p, d_p, F_star = self.unload_curve(d_star)
        Kp = 4 / 3 * self.E * math.sqrt(R_p)

        def rhs_unload(_t, y):
            return [y[1], -Kp * max(y[0] - d_p, 0.0) ** 1.5 / m]

        def sep(_t, y):
            return y[0] - d_p
        sep.terminal, sep.direction = True, -1
        s2 = solve_ivp(rhs_unload, (0, 1e3 * t0), [d_star, 0.0], method="DOP853", rtol=IMPACT_RTOL,
                       atol=[IMPACT_ATOL * d0, IMPACT_ATOL * V], events=sep)
        return -s2.y_events[0][0][1] / V, s1.t_events[0][0] + s2.t_events[0][0], d_star, F_star


def thornton_restitution(r):
    """Thornton's closed-form restitution for r = V_Y/V in (0, 1]; 1 at r >= 1 (elastic impact)."""
    if r >= 1:
        return 1.0
    return (math.sqrt(6 * math.sqrt(3) / 5) * math.sqrt(1 - r * r / 6)
            * (r / (r + 2 * math.sqrt(6 / 5 - r * r / 5))) ** 0.25)


def hertz_impact_closed_form(m, K, V):
    """(delta_max, F_max, contact time) of an undamped Hertz impact (Johnson 1985, ch. 11)."""
    d = (1.25 * m * V * V / K) ** 0.4
    # t_c = 2 delta_max/V int_0^1 (1 - x^2.5)^(-1/2) dx, the integral = 2/5 B(2/5, 1/2)
    shape = 0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
    return d, K * d ** 1.5, 2 * shape * d / V


def restitution_table(targets=(0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)):
    """Rows (e, Hunt-Crossley, Lankarani-Nikravesh, Flores, Tsuji alpha, linear zeta): the restitution each
    published form really gives when asked for e (by integration), and the exact forms' constants."""
    return [(e, *(hc_restitution(f, e) for f in sorted(FORMULAS)), tsuji_alpha(e), linear_zeta(e)) for e in targets]


def main():
    """python -m vibroimpact.reference.laws: the tables of restitutions and released energies doc/model.md
    quotes."""
    print("| e_restitution | hunt_crossley | lankarani_nikravesh | flores | exact: alpha | linear: zeta |")
    print("|---|---|---|---|---|---|")
    for row in restitution_table():
        print("| {:.1f} | {:.4f} | {:.4f} | {:.4f} | {:.6f} | {:.6f} |".format(*row))
    print()
    print("| e_restitution | exact: released | linear: released |")
    print("|---|---|---|")
    for e in (0.3, 0.5, 0.7, 0.9):
        exact, linear = (100 * released_fraction(law, e) for law in ("exact", "linear"))
        print(f"| {e:.1f} | {exact:.2f} % | {linear:.2f} % |")


if __name__ == "__main__":
    main()
