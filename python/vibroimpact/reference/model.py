"""Independent reference implementation of the VibroImpact hybrid model.

Written from the model's definition (doc/model.md) and the source paper
(Kowalska 2002, "Modelling and simulation of dynamic unilateral elasto-plastic
contact of compact hard bodies") only; it does not use the C implementation.  Units are SI throughout (m, s, N, J).

System (vertical axis up)
-------------------------
    platform     yC(t) = yC_in + a (cos(2 pi f t) - 1)
    indentation  delta = yC - y          (> 0: bodies pressed together)
    motion       m y'' = F - W,   W = P + m g - F_ext      (net downward load)

The continuous state is (delta, v) with v = y' the mass velocity (up positive):

    delta' = yC'(t) - v
    v'     = (F - W) / m          (F = 0 in free flight)

A third, passive state w = int F yC' dt (work done by the platform on the mass
through the contact) is integrated alongside for the energy balance; it is
excluded from the step-size control (see ``_tolerances``).

Effective properties, paper eq. (1)
-----------------------------------
    1/R* = 1/R1 + 1/R2   (R = 0 means a plane, 1/R = 0)
    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
    K    = 4/3 E* sqrt(R*)

Yield limit, paper eq. (5)
--------------------------
    textbook (yield_formula 1): F_Y = pi (3 pi/4)^2 (theta_Y Y)^3 R*^2 / E*^2
    printed  (yield_formula 2): F_Y =    (3 pi/4)^2 (theta_Y Y)^3 R*^2 / E*^2
    delta_Y = (F_Y / K)^(2/3)  (Hertz, eq. 2),   k_lin = F_Y / delta_Y

Contact laws
------------
Hertz, eq. (2):          F = K delta^1.5                   (mode 1 only)
Johnson virgin curve:    F = K delta^1.5                   delta <= delta_Y (mode 1)
                  eq (3) F = F_Y k [1 + ln(k)/(3 theta_Y)], k = 2 delta/delta_Y - 1
                                                           delta >  delta_Y (mode 2)
Johnson unloading/reloading, eq. (4), after a maximum indentation delta_c:
                         F = 4/3 E* sqrt(Rbar) (delta - delta_f)^1.5   (mode 3)
    paper:      k_c = 2 delta_c/delta_Y - 1, Rbar = R* sqrt(k_c),
                delta_r = delta_Y sqrt(k_c),  delta_f = delta_c - delta_r
                (so F_unload(delta_c) = F_Y k_c < F_load(delta_c))
    continuous: F_c = F_load(delta_c), a_c^2 = R* (2 delta_c - delta_Y),
                delta_r = min(3 F_c / (4 E* a_c), 5/2 W_virgin(delta_c) / F_c),
                Rbar from F_c = 4/3 E* sqrt(Rbar) delta_r^1.5 (force continuous; the
                curve returns 2/5 F_c delta_r <= W_virgin(delta_c): passive; with
                the first term, Rbar = 4 E* a_c^3 / (3 F_c): radius continuous too)
    Reloading to delta_c continues on the virgin curve (mode 2) and raises
    delta_c; separation when delta < delta_f (free flight, mode 0), re-contact
    at delta = delta_f on the unloading curve (mode 3).
Johnson, moving contact: F = virgin curve both ways, mode 1 below delta_Y,
    mode 2 above; no memory.
LEPP (linear elastic - perfectly plastic, paper Fig. 3):
    F = k_lin (delta - delta_p) for delta_p < delta <= delta_p + delta_Y (mode 1)
    F = F_Y, delta_p = delta - delta_Y while delta grows at F = F_Y (mode 2).

Thornton (contact_model 6): Johnson's fixed-contact-point automaton with
    Thornton's virgin curve (Hertz, then F_Y + 1.5 F_Y/delta_Y (delta -
    delta_Y)) and his unloading curve (laws.py); force continuous at delta_c.
Damped Hertz (4) and the linear spring-dashpot (5): F = max(0, f(delta,
    delta')), f of laws.py (modes 0 and 1 only). Contact while delta > 0 and
    f > 0: mode 1 is left when delta falls through 0 ("separation") or the
    guard g (the sign of f, laws.py) does ("release": the rate is snapped
    onto g = 0); mode 0 when delta rises through 0 ("contact": a new contact,
    V_i = delta') or g rises through 0 while delta > 0 ("resume", V_i kept).
    A contact present at a static start has V_i = 0 (undamped published
    forms until it ends); init touching has V_i = yC'(0) - v0.

Stick (Filippov sliding, paper unloading): at delta = delta_c with
delta' = 0, F_hold = W + m yC''(t). If F_unload(delta_c) <= F_hold <=
F_load(delta_c) neither branch is consistent; the mass moves with the
platform: delta = delta_c, v = yC'(t), F = F_hold (mode 4), until F_hold
leaves the interval.

Energies
--------
U (stored elastic): Hertz / virgin elastic 2/5 K delta^2.5; unloading curve
2/5 Kbar (delta - delta_f)^2.5 (in mode 2 and 4 with the current delta_c);
moving contact above delta_Y: the virgin-curve work int_0^delta F; LEPP
F^2/(2 k_lin).
W_plastic: Johnson fixed contact int_0^delta_c F_load - 2/5 F_unload(delta_c)
delta_r (delta_c = delta while loading plastically); LEPP F_Y delta_p; else 0.
Balance: 1/2 m v^2 + U + W_plastic + W (y - y(0)) - w = const.

Modes and switching surfaces (g = 0 crossed in the given direction)
--------------------------------------------------------------------
    0 free       delta - s_c  rising  -> contact  (s_c = 0, delta_f after a
                                         Johnson yield, delta_p for LEPP)
    1 elastic    delta - s_c  falling -> separation
                 delta - delta_Y (LEPP: delta_p + delta_Y) rising -> yield
    2 plastic    Johnson fixed, LEPP: delta' falling through 0 -> turn
                   (commits delta_c = delta, resp. delta_p = delta - delta_Y)
                 moving contact: delta - delta_Y falling -> unyield
    3 unload     delta - delta_f falling -> separation
                 delta - delta_c rising  -> reload (back to the virgin curve)
    4 stick      F_hold - F_unload(delta_c) falling -> release_unload
                 F_hold - F_load(delta_c)   rising  -> release_load

Mode resolver (``Model.resolve``), used at t = 0 and after every event: for
each surface (a constant indentation, given the memory) the side of the state
is the sign of the first non-vanishing entry of (delta - s, delta', delta'',
delta'''), with delta'' = yC'' - (F(s) - W)/m evaluated with the force on the
surface (the same on both sides except at delta_c with paper unloading) and
delta''' = yC''' once delta' = 0. Contact needs the positive side of s_c;
plastic the positive side of the yield surface. At delta = delta_c with
delta' = 0 (Johnson with memory): loading (2) if F_hold > F_load(delta_c),
unloading (3) if F_hold < F_unload(delta_c) (ties decided by the sign of
F_hold' = m yC'''), stick (4) otherwise. Events after which the mode is
unchanged are not reported. n_impacts counts transitions out of mode 0.

Initial state (init)
--------------------
static: at rest, v = yC'(0), delta0 on the virgin curve under W (Hertz:
(W/K)^(2/3); Johnson: eq. (3) solved for W > F_Y, and with a fixed contact
point the memory delta_c = delta0 is committed (pre-loaded), after which
the resolver picks stick/unloading/loading; LEPP: W/k_lin, W > F_Y has no
equilibrium and is rejected; W <= 0: delta0 = 0). touching: delta = 0, v = v0.

Output conventions
------------------
Before any yield (and always for Hertz, moving contact and LEPP):
delta_c = delta_f = 0, Rbar = R*. In mode 2 (Johnson fixed) delta_c, delta_f,
Rbar, W_plastic, U are those of delta_c = delta. delta_p is 0 except for
LEPP (live delta - delta_Y in mode 2). moving_contact only affects Johnson.
F is clamped at 0 in the outputs; in stick F = F_hold.

Numerical method
----------------
scipy.integrate.solve_ivp, DOP853, one terminal event function per switching
surface of the current mode, with direction; events are located by brentq on
the dense output. After each event the state is snapped onto the surface
(delta = surface value, or v = yC'(t) at a turn / stick release), the memory
updated and the next mode chosen by the resolver. Inside a mode the force
law is continued smoothly past the surfaces where possible (eq. 3 below
delta_Y, Hertz above delta_Y, the LEPP spring below delta_p), so that the
step that overshoots a surface sees a smooth vector field. The Hertz-type
onset / separation (F ~ (delta - s)^1.5) is not smooth; there the step is
limited to ``_singular_step`` (first step after an onset; graded re-runs of
the last step before a separation). atol: see ``_tolerances`` and
``Model.reference_scales``; max step: ``_max_step``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import OdeSolution, solve_ivp
from scipy.optimize import brentq

from . import laws

# Enumeration codes (FMU interface).
HERTZ, JOHNSON, LEPP, HERTZ_DAMPED, LINEAR, THORNTON = 1, 2, 3, 4, 5, 6
PAPER, CONTINUOUS = 1, 2
TEXTBOOK, PRINTED = 1, 2
STATIC, TOUCHING = 1, 2

# Modes.
FREE, ELASTIC, PLASTIC, UNLOAD, STICK = 0, 1, 2, 3, 4

DEFAULTS = dict(
    m=407.747, P=40000.0, g=9.81,            # kg, N, m/s2
    R1=0.475, R2=0.0,                        # m (0 = plane)
    E1=2.1e11, E2=2.1e11, nu1=0.3, nu2=0.3,  # Pa, 1
    Y=6e8, theta_Y=1.1,                      # Pa, 1
    contact_model=JOHNSON, moving_contact=False, unloading=PAPER,
    yield_formula=TEXTBOOK, init=STATIC,
    e_restitution=0.8, damping_formula=laws.EXACT,  # 1; damped Hertz and linear
    k_spring=1.2e9,                          # N/m, linear
    v0=0.0,                                  # m/s
    a=0.0, f=560.0,                          # m, Hz
    F_ext=0.0, yC_in=0.0,                    # N, m
)

ZENO_WINDOW = 1e-9      # s: events closer than this count as "at one instant"
ZENO_MAX_EVENTS = 10000  # events allowed within one such window


class ZenoError(RuntimeError):
    """Raised when the event sequence accumulates at one instant."""


# --------------------------------------------------------------------------
# Parameters and derived quantities
# --------------------------------------------------------------------------

def full_params(params: dict | None) -> dict:
    """Return the defaults updated with ``params``; reject unknown names."""
    p = dict(DEFAULTS)
    for key, value in (params or {}).items():
        if key not in DEFAULTS:
            raise KeyError(f"unknown parameter {key!r}")
        p[key] = value
    return p


def derived(params: dict | None) -> dict:
    """Derived contact constants (paper eqs. 1, 2, 5)."""
    p = full_params(params)
    inv_r = sum(1.0 / r for r in (p["R1"], p["R2"]) if r != 0.0)
    if inv_r <= 0.0:
        raise ValueError("R1 and R2 cannot both be planes")
    R_star = 1.0 / inv_r                                           # m
    E_star = 1.0 / ((1 - p["nu1"] ** 2) / p["E1"]
                    + (1 - p["nu2"] ** 2) / p["E2"])               # Pa
    K = 4.0 / 3.0 * E_star * math.sqrt(R_star)                     # N/m^1.5
    p_Y = p["theta_Y"] * p["Y"]                                    # Pa
    F_Y = (3 * math.pi / 4) ** 2 * p_Y ** 3 * R_star ** 2 / E_star ** 2
    if p["yield_formula"] == TEXTBOOK:
        F_Y *= math.pi
    elif p["yield_formula"] != PRINTED:
        raise ValueError("yield_formula must be 1 (textbook) or 2 (printed)")
    delta_Y = (F_Y / K) ** (2.0 / 3.0)                             # m
    return dict(E_star=E_star, R_star=R_star, K=K, F_Y=F_Y,
                delta_Y=delta_Y, k_lin=F_Y / delta_Y)


def lex_sign(*pairs) -> int:
    """Sign of the first entry whose magnitude exceeds its tolerance.

    ``pairs`` are (value, tol) in order of priority (position, rate,
    acceleration, ...). Returns 0 if all entries vanish.
    """
    for value, tol in pairs:
        if value > tol:
            return 1
        if value < -tol:
            return -1
    return 0


# --------------------------------------------------------------------------
# Plastic memory
# --------------------------------------------------------------------------

@dataclass(frozen=True)
class Memory:
    """Discrete state besides the mode (all lengths in m, forces in N)."""
    yielded: bool = False      # Johnson fixed contact: delta_c committed
    delta_c: float = 0.0       # maximum indentation
    delta_r: float = 0.0       # elastic recovery delta_c - delta_f
    delta_f: float = 0.0       # permanent set (zero-force point of eq. 4)
    Rbar: float = 0.0          # effective radius after plastic deformation
    Kbar: float = 0.0          # 4/3 E* sqrt(Rbar)
    F_unload_c: float = 0.0    # unloading-curve force at delta_c
    F_load_c: float = 0.0      # virgin-curve force at delta_c
    delta_p: float = 0.0       # LEPP permanent set
    delta_yield: float = 0.0   # LEPP yield surface delta_p + delta_Y (stored
    #                            exactly so that snapping is exact)
    V_i: float = 0.0           # damped Hertz, published forms: approach speed
    #                            at the onset of this contact (m/s)


# --------------------------------------------------------------------------
# The model: contact laws, modes, surfaces, resolver
# --------------------------------------------------------------------------

class Model:
    """Contact laws, vector fields, switching surfaces and mode resolver."""

    def __init__(self, params: dict | None):
        p = self.p = full_params(params)
        d = self.d = derived(p)
        self.m = float(p["m"])
        self.W = p["P"] + p["m"] * p["g"] - p["F_ext"]     # N, net load down
        self.E_star, self.R_star, self.K = d["E_star"], d["R_star"], d["K"]
        self.F_Y, self.delta_Y, self.k_lin = d["F_Y"], d["delta_Y"], d["k_lin"]
        self.theta = p["theta_Y"]
        if p["contact_model"] == HERTZ:
            self.law = "hertz"
        elif p["contact_model"] == JOHNSON:
            self.law = "moving" if p["moving_contact"] else "johnson"
        elif p["contact_model"] == LEPP:
            self.law = "lepp"
        elif p["contact_model"] in (HERTZ_DAMPED, LINEAR):
            self.law = "damped"
            self._setup_damping(p)
        elif p["contact_model"] == THORNTON:
            self.law = "thornton"
        else:
            raise ValueError("contact_model must be 1 ... 6")
        # laws with a fixed-contact-point plastic memory (delta_c, unloading curve)
        self.fixed_plastic = self.law in ("johnson", "thornton")
        if p["unloading"] not in (PAPER, CONTINUOUS):
            raise ValueError("unloading must be 1 (paper) or 2 (continuous)")
        self.continuous = p["unloading"] == CONTINUOUS
        self.a, self.omega = float(p["a"]), 2 * math.pi * p["f"]   # m, rad/s
        self.yC_in = float(p["yC_in"])
        # Tolerances of the resolver on force-like quantities: the event
        # time of a stick release is exact to ~1e-15 s, so F_hold is exact
        # to m a omega^3 * 1e-15 ~ 1e-6 N; 1e-9 of the force scale is far
        # above that and far below any physical force difference.
        f_scale = max(abs(self.W), self.F_Y, self.m * self.a * self.omega ** 2)
        self.tol_F = 1e-9 * f_scale                       # N
        self.tol_acc = self.tol_F / self.m                # m/s2

    # ---- platform -------------------------------------------------------
    def yC(self, t):
        return self.yC_in + self.a * (np.cos(self.omega * t) - 1.0)

    def yC1(self, t: float) -> float:
        """Platform velocity (m/s)."""
        return -self.a * self.omega * math.sin(self.omega * t)

    def yC2(self, t: float) -> float:
        """Platform acceleration (m/s2)."""
        return -self.a * self.omega ** 2 * math.cos(self.omega * t)

    def yC3(self, t: float) -> float:
        """Platform jerk (m/s3)."""
        return self.a * self.omega ** 3 * math.sin(self.omega * t)

    def F_hold(self, t: float) -> float:
        """Contact force that keeps delta constant (N)."""
        return self.W + self.m * self.yC2(t)

    # ---- force laws -----------------------------------------------------
    def F_virgin(self, delta: float) -> float:
        """Virgin loading curve: Hertz (eq. 2) then Johnson (eq. 3), or Thornton's line."""
        if delta <= self.delta_Y:
            return self.K * max(delta, 0.0) ** 1.5
        if self.law == "thornton":
            return self.F_johnson_load(delta)
        k = 2.0 * delta / self.delta_Y - 1.0
        return self.F_Y * k * (1.0 + math.log(k) / (3.0 * self.theta))

    def F_johnson_load(self, delta: float) -> float:
        """Eq. (3) continued analytically below delta_Y (down to delta_Y/2).

        Used as the vector field of mode 2 so that a step overshooting the
        surface delta = delta_Y sees a smooth right-hand side. Thornton: the
        line F_Y + pi p_Y R* (delta - delta_Y), pi p_Y R* = 1.5 F_Y/delta_Y.
        """
        if self.law == "thornton":
            return self.F_Y * (1.0 + 1.5 * (delta / self.delta_Y - 1.0))
        k = max(2.0 * delta / self.delta_Y - 1.0, 1e-300)
        return self.F_Y * k * (1.0 + math.log(k) / (3.0 * self.theta))

    def W_virgin(self, delta: float) -> float:
        """Work along the virgin curve from 0 to delta (J), closed form."""
        if delta <= self.delta_Y:
            return 0.4 * self.K * max(delta, 0.0) ** 2.5
        if self.law == "thornton":
            x = delta - self.delta_Y
            return 0.4 * self.F_Y * self.delta_Y + self.F_Y * x + 0.75 * self.F_Y / self.delta_Y * x * x
        k = 2.0 * delta / self.delta_Y - 1.0
        k2 = k * k
        integral = 0.5 * (k2 - 1.0) + (0.5 * k2 * math.log(k) - 0.25 * (k2 - 1.0)) \
            / (3.0 * self.theta)
        return 0.4 * self.F_Y * self.delta_Y + 0.5 * self.F_Y * self.delta_Y * integral

    def johnson_memory(self, delta_c: float) -> Memory:
        """Unloading-curve constants (eq. 4) for a maximum indentation delta_c."""
        F_load_c = self.F_virgin(delta_c)
        if self.law == "thornton":
            # Thornton 1997: Hertzian unloading with a_p^2 = (2 F_c + F_Y)/(2 pi p_Y), p_Y the maximum
            # Hertz pressure at yield, 2 pi p_Y = 3 F_Y/(R* delta_Y)
            ap2 = (2 * F_load_c + self.F_Y) * self.R_star * self.delta_Y / (3 * self.F_Y)
            Rbar = 4.0 * self.E_star * ap2 ** 1.5 / (3.0 * F_load_c)
            delta_r = (3.0 * F_load_c / (4.0 * self.E_star * math.sqrt(Rbar))) ** (2.0 / 3.0)
        elif self.continuous:
            # the Hertz curve through (delta_c, F_c) whose returned energy 2/5 F_c delta_r is the smaller
            # of the radius-continuous curve's and the virgin work: passive
            a_c = math.sqrt(self.R_star * (2.0 * delta_c - self.delta_Y))
            delta_r = min(3.0 * F_load_c / (4.0 * self.E_star * a_c), 2.5 * self.W_virgin(delta_c) / F_load_c)
            Rbar = (3.0 * F_load_c / (4.0 * self.E_star)) ** 2 / delta_r ** 3
        else:
            k_c = 2.0 * delta_c / self.delta_Y - 1.0
            Rbar = self.R_star * math.sqrt(k_c)
            delta_r = self.delta_Y * math.sqrt(k_c)
        Kbar = 4.0 / 3.0 * self.E_star * math.sqrt(Rbar)
        return Memory(yielded=True, delta_c=delta_c, delta_r=delta_r,
                      delta_f=delta_c - delta_r, Rbar=Rbar, Kbar=Kbar,
                      F_unload_c=Kbar * delta_r ** 1.5, F_load_c=F_load_c)

    def lepp_memory(self, delta_yield: float) -> Memory:
        """LEPP memory with yield surface at delta_yield = delta_p + delta_Y."""
        return Memory(delta_p=delta_yield - self.delta_Y, delta_yield=delta_yield)

    def initial_memory(self) -> Memory:
        return Memory(Rbar=self.R_star, Kbar=self.K, delta_yield=self.delta_Y)

    def contact_surface(self, mem: Memory) -> float:
        """Indentation at which contact starts / ends (m)."""
        if self.fixed_plastic and mem.yielded:
            return mem.delta_f
        if self.law == "lepp":
            return mem.delta_p
        return 0.0

    def force_fn(self, mode: int, mem: Memory):
        """Contact force as a function of (t, delta, v) in ``mode`` (N)."""
        if mode == FREE:
            return lambda t, d, v: 0.0
        if mode == STICK:
            return lambda t, d, v: self.F_hold(t)
        if self.law == "damped":            # unclamped (smooth at separation)
            f, yC1 = self.damped_fn(mem), self.yC1
            return lambda t, d, v: f(d, yC1(t) - v)
        if self.law == "hertz":
            K = self.K
            return lambda t, d, v: K * d ** 1.5 if d > 0.0 else 0.0
        if self.law == "lepp":
            if mode == PLASTIC:
                F_Y = self.F_Y
                return lambda t, d, v: F_Y
            k, dp = self.k_lin, mem.delta_p      # continued linearly below
            return lambda t, d, v: k * (d - dp)  # delta_p (smooth at separation)
        if mode == UNLOAD:
            Kbar, df = mem.Kbar, mem.delta_f
            return lambda t, d, v: Kbar * (d - df) ** 1.5 if d > df else 0.0
        if mode == ELASTIC:
            K = self.K
            return lambda t, d, v: K * d ** 1.5 if d > 0.0 else 0.0
        return lambda t, d, v: self.F_johnson_load(d)

    # ---- damped Hertz and the linear spring-dashpot (reference/laws.py) --
    def _setup_damping(self, p: dict) -> None:
        e, formula = float(p["e_restitution"]), int(p["damping_formula"])
        if not 0.0 < e <= 1.0:
            raise ValueError("e_restitution must lie in (0, 1]")
        self.linear = p["contact_model"] == LINEAR
        if self.linear:
            if not p["k_spring"] > 0:
                raise ValueError("k_spring must be > 0")
            self.k_spring = float(p["k_spring"])
            self.c_damp = 2 * laws.linear_zeta(e) * math.sqrt(self.m * self.k_spring)
            return
        self.formula = formula
        if formula == laws.EXACT:
            self.alpha_c = laws.tsuji_alpha(e) * math.sqrt(self.m * self.K)
        else:
            self.chi = laws.chi(formula, e)

    def damped_fn(self, mem: Memory):
        """f(delta, rate): the unclamped force (N) at indentation delta and rate d(delta)/dt."""
        if self.linear:
            k, c = self.k_spring, self.c_damp
            return lambda d, r: k * d + c * r
        K = self.K
        if self.formula == laws.EXACT:
            a = self.alpha_c
            return lambda d, r: K * max(d, 0.0) ** 1.5 + a * max(d, 0.0) ** 0.25 * r
        b = self.chi / mem.V_i if mem.V_i > 0.0 else 0.0   # undamped after a start at rest
        return lambda d, r: K * max(d, 0.0) ** 1.5 * (1.0 + b * r)

    def damped_guard(self, mem: Memory):
        """(g, dg/d delta, dg/d rate): g has the sign of the unclamped force for delta > 0 and is
        finite at delta = 0 (f/delta^(1/4) for Tsuji's form, f/(K delta^1.5) for the published forms)."""
        if self.linear:
            k, c = self.k_spring, self.c_damp
            return lambda d, r: (k * d + c * r, k, c)
        if self.formula == laws.EXACT:
            K, a = self.K, self.alpha_c
            return lambda d, r: (K * max(d, 0.0) ** 1.25 + a * r, 1.25 * K * max(d, 0.0) ** 0.25, a)
        b = self.chi / mem.V_i if mem.V_i > 0.0 else 0.0
        return lambda d, r: (1.0 + b * r, 0.0, b)

    # ---- energies -------------------------------------------------------
    def stored_and_plastic(self, mode: int, mem: Memory, delta: float):
        """(U, W_plastic, delta_c, delta_f, delta_p, Rbar) shown in ``mode``.

        U: stored elastic energy (J); W_plastic: plastic work so far (J).
        """
        R, dY, in_contact = self.R_star, self.delta_Y, mode != FREE
        if self.law == "hertz" or (self.law == "damped" and not self.linear):
            U = 0.4 * self.K * max(delta, 0.0) ** 2.5 if in_contact else 0.0
            return U, 0.0, 0.0, 0.0, 0.0, R
        if self.law == "damped":    # linear spring
            return (0.5 * self.k_spring * delta * delta if in_contact else 0.0), 0.0, 0.0, 0.0, 0.0, R
        if self.law == "moving":            # path-independent virgin curve
            U = self.W_virgin(delta) if in_contact else 0.0
            return U, 0.0, 0.0, 0.0, 0.0, R
        if self.law == "lepp":
            if mode == PLASTIC:             # live permanent set
                dp = delta - dY
                return 0.5 * self.F_Y * dY, self.F_Y * dp, 0.0, 0.0, dp, R
            F = self.k_lin * max(delta - mem.delta_p, 0.0) if in_contact else 0.0
            return (F * F / (2 * self.k_lin), self.F_Y * mem.delta_p,
                    0.0, 0.0, mem.delta_p, R)
        # Johnson and Thornton, fixed contact point
        if mode == PLASTIC:
            mem = self.johnson_memory(delta)        # live: delta_c = delta
        if not mem.yielded:
            U = 0.4 * self.K * max(delta, 0.0) ** 2.5 if in_contact else 0.0
            return U, 0.0, 0.0, 0.0, 0.0, R
        U_c = 0.4 * mem.F_unload_c * mem.delta_r    # unloading curve at delta_c
        Wp = self.W_virgin(mem.delta_c) - U_c
        if mode in (PLASTIC, STICK):
            U = U_c
        elif mode == UNLOAD:
            U = 0.4 * mem.Kbar * max(delta - mem.delta_f, 0.0) ** 2.5
        else:
            U = 0.0
        return U, Wp, mem.delta_c, mem.delta_f, 0.0, mem.Rbar

    # ---- vector field ---------------------------------------------------
    def rhs(self, mode: int, mem: Memory):
        """Right-hand side f(t, [delta, v, w]) of ``mode``."""
        m, W, yC1, yC2 = self.m, self.W, self.yC1, self.yC2
        if mode == STICK:
            Fh = self.F_hold
            return lambda t, y: (0.0, yC2(t), Fh(t) * yC1(t))
        F = self.force_fn(mode, mem)

        def f(t, y):
            u = yC1(t)
            Fc = max(F(t, y[0], y[1]), 0.0)
            return (u - y[1], (Fc - W) / m, Fc * u)
        return f

    # ---- switching surfaces ---------------------------------------------
    def surfaces(self, mode: int, mem: Memory):
        """List of (g(t, y), direction, kind) active in ``mode``."""
        s_c = self.contact_surface(mem)
        if self.law == "damped":
            # in contact while delta > 0 and the unclamped force > 0 (its guard g > 0): a new contact
            # when delta rises through 0, a resumed one when g does while delta > 0
            g, yC1 = self.damped_guard(mem), self.yC1
            if mode == FREE:
                return [(lambda t, y: y[0], +1, "contact"),
                        (lambda t, y: max(-y[0], -g(y[0], yC1(t) - y[1])[0]), -1, "resume")]
            return [(lambda t, y: y[0], -1, "separation"),
                    (lambda t, y: g(y[0], yC1(t) - y[1])[0], -1, "release")]
        if mode == FREE:
            return [(lambda t, y: y[0] - s_c, +1, "contact")]
        if mode == STICK:
            Fu, Fl, Fh = mem.F_unload_c, mem.F_load_c, self.F_hold
            return [(lambda t, y: Fh(t) - Fu, -1, "release_unload"),
                    (lambda t, y: Fh(t) - Fl, +1, "release_load")]
        separation = (lambda t, y: y[0] - s_c, -1, "separation")
        turn = (lambda t, y: self.yC1(t) - y[1], -1, "turn")
        if self.law == "hertz":
            return [separation]
        if self.law == "lepp":
            if mode == ELASTIC:
                dy = mem.delta_yield
                return [separation, (lambda t, y: y[0] - dy, +1, "yield")]
            return [turn]
        dY = self.delta_Y
        if self.law == "moving":
            if mode == ELASTIC:
                return [separation, (lambda t, y: y[0] - dY, +1, "yield")]
            return [(lambda t, y: y[0] - dY, -1, "unyield")]
        # Johnson, fixed contact point
        if mode == ELASTIC:
            return [separation, (lambda t, y: y[0] - dY, +1, "yield")]
        if mode == PLASTIC:
            return [turn]
        dc = mem.delta_c
        return [separation, (lambda t, y: y[0] - dc, +1, "reload")]

    def snap(self, kind: str, t: float, delta: float, v: float, mem: Memory):
        """Put the state exactly on the surface ``kind`` and update memory."""
        if kind == "release":
            # the force through 0 while the bodies overlap: the rate onto g = 0 (g is linear in it)
            g, _, g_r = self.damped_guard(mem)(delta, self.yC1(t) - v)
            v += g / g_r
        elif kind == "resume":
            pass
        elif kind == "contact" and self.law == "damped":   # a new contact: its approach speed
            delta, mem = 0.0, Memory(V_i=max(self.yC1(t) - v, 0.0))
        elif kind in ("contact", "separation"):
            delta = self.contact_surface(mem)
        elif kind in ("yield", "unyield"):
            delta = mem.delta_yield if self.law == "lepp" else self.delta_Y
        elif kind == "reload":
            delta = mem.delta_c
        elif kind == "turn":
            v = self.yC1(t)
            if self.fixed_plastic:
                mem = self.johnson_memory(delta)
            elif self.law == "lepp":
                mem = self.lepp_memory(delta)
        elif kind in ("release_unload", "release_load"):
            delta, v = mem.delta_c, self.yC1(t)
        return delta, v, mem

    # ---- mode resolver --------------------------------------------------
    def resolve(self, t: float, delta: float, v: float, mem: Memory) -> int:
        """Consistent mode for the state (t, delta, v) and memory ``mem``.

        For each surface s (a constant indentation given the memory) the side
        is the sign of the first non-vanishing entry of (delta - s, delta',
        delta'', delta''') where delta'' = yC'' - (F(s) - W)/m uses the force
        on the surface (continuous there except at delta_c with paper
        unloading) and delta''' = yC''' once delta' = 0.
        """
        r = self.yC1(t) - v                                  # delta' (m/s)
        acc = lambda F: self.yC2(t) - (F - self.W) / self.m   # delta'' (m/s2)
        jerk = (self.yC3(t), 0.0)
        side = lambda s, F: lex_sign((delta - s, 0.0), (r, 0.0),
                                     (acc(F), self.tol_acc), jerk)
        if side(self.contact_surface(mem), 0.0) <= 0:
            return FREE
        if self.law == "damped":
            # the sign of g, then of its rate with F = 0 on the surface g = 0; g within 1e-9 of the
            # size of its terms counts as 0
            g, g_d, g_r = self.damped_guard(mem)(delta, r)
            tol_g = 1e-9 * (abs(g - g_r * r) + abs(g_r * r))
            return ELASTIC if lex_sign((g, tol_g), (g_d * r + g_r * acc(0.0), 0.0)) > 0 else FREE
        if self.law == "hertz":
            return ELASTIC
        if self.law == "lepp":
            return PLASTIC if side(mem.delta_yield, self.F_Y) > 0 else ELASTIC
        if self.law == "moving" or not mem.yielded:
            return PLASTIC if side(self.delta_Y, self.F_Y) > 0 else ELASTIC
        # Johnson and Thornton with memory: unloading curve below delta_c, virgin above
        if delta != mem.delta_c:
            return PLASTIC if delta > mem.delta_c else UNLOAD
        if r != 0.0:
            return PLASTIC if r > 0.0 else UNLOAD
        Fh, dFh = self.F_hold(t), (self.m * self.yC3(t), 0.0)
        if lex_sign((Fh - mem.F_load_c, self.tol_F), dFh) > 0:
            return PLASTIC          # loading branch consistent (delta'' > 0)
        if lex_sign((Fh - mem.F_unload_c, self.tol_F), dFh) < 0:
            return UNLOAD           # unloading branch consistent (delta'' < 0)
        return STICK

    # ---- initial state --------------------------------------------------
    def initial_state(self):
        """(delta, v, memory) at t = 0 according to ``init``."""
        mem = self.initial_memory()
        v_platform = self.yC1(0.0)
        if self.p["init"] == TOUCHING:
            if self.law == "damped":   # an impact at the start: its approach speed
                mem = Memory(V_i=max(v_platform - float(self.p["v0"]), 0.0))
            return 0.0, float(self.p["v0"]), mem
        if self.p["init"] != STATIC:
            raise ValueError("init must be 1 (static) or 2 (touching)")
        W = self.W
        if W <= 0.0:
            return 0.0, v_platform, mem
        if self.law == "damped":   # at rest: the springs carry W (a contact at rest: V_i = 0)
            d0 = W / self.k_spring if self.linear else (W / self.K) ** (2.0 / 3.0)
            return d0, v_platform, mem
        if self.law == "lepp":
            if W > self.F_Y:
                raise ValueError("LEPP: no static equilibrium for W > F_Y "
                                 "(perfectly plastic flow under constant load)")
            return W / self.k_lin, v_platform, mem
        delta0 = (W / self.K) ** (2.0 / 3.0)
        if self.law == "hertz" or delta0 <= self.delta_Y:
            return delta0, v_platform, mem
        hi = self.delta_Y
        while self.F_virgin(hi) < W:
            hi *= 2.0
        delta0 = brentq(lambda d: self.F_virgin(d) - W, self.delta_Y, hi,
                        xtol=1e-16, rtol=4 * np.finfo(float).eps)
        if self.fixed_plastic:
            mem = self.johnson_memory(delta0)    # plastically pre-loaded
        return delta0, v_platform, mem

    # ---- tolerances -----------------------------------------------------
    def reference_scales(self):
        """Characteristic indentation (m) and velocity (m/s) for atol.

        delta_ref = min(delta_Y, Hertz indentation under |W|) (delta_Y if
        W = 0); v_ref = max(omega_c delta_ref, a 2 pi f, |v0|) with omega_c
        the linearised Hertz contact frequency at delta_ref.
        """
        d_ref = self.delta_Y
        if self.W != 0.0:
            d_ref = min(d_ref, (abs(self.W) / self.K) ** (2.0 / 3.0))
        omega_c = math.sqrt(1.5 * self.K * math.sqrt(d_ref) / self.m)
        v_ref = max(omega_c * d_ref, self.a * self.omega, abs(self.p["v0"]))
        return d_ref, v_ref


# --------------------------------------------------------------------------
# Simulation
# --------------------------------------------------------------------------

@dataclass
class Segment:
    """A stretch of integration in one mode with fixed memory."""
    t0: float
    t1: float
    mode: int
    mem: Memory
    y0: np.ndarray             # state right after the event at t0 (snapped)
    sol: object = None         # OdeSolution on [t0, t1] (None if t1 == t0)
    ts: np.ndarray = None      # solver step times

    def state(self, t: np.ndarray) -> np.ndarray:
        """(3, len(t)) state; exactly y0 at t0."""
        if self.sol is None:
            return np.repeat(self.y0[:, None], len(t), axis=1)
        y = np.asarray(self.sol(t)).reshape(3, len(t))
        y[:, t == self.t0] = self.y0[:, None]
        return y


@dataclass
class Result:
    """Outputs sampled at ``t`` (see module docstring for the symbols)."""
    t: np.ndarray
    delta: np.ndarray
    v: np.ndarray
    y: np.ndarray
    yC: np.ndarray
    F: np.ndarray
    mode: np.ndarray
    delta_c: np.ndarray
    delta_f: np.ndarray
    delta_p: np.ndarray
    Rbar: np.ndarray
    W_plastic: np.ndarray
    n_impacts: np.ndarray
    U: np.ndarray              # stored elastic energy (J)
    W_platform: np.ndarray     # int F yC' dt (J)
    events: list = field(default_factory=list)   # (t, mode_before, mode_after, kind)
    n_impacts_total: int = 0
    n_segments: int = 0
    n_steps: int = 0
    params: dict = field(default_factory=dict)

    def energy_residual(self) -> np.ndarray:
        """Balance 1/2 m v^2 + U + W_plastic + W (y - y[0]) - W_platform
        minus its value at the first sample (J); zero for an exact solution
        (W = P + m g - F_ext)."""
        p = self.params
        W = p["P"] + p["m"] * p["g"] - p["F_ext"]
        e = 0.5 * p["m"] * self.v ** 2 + self.U + self.W_plastic \
            + W * (self.y - self.y[0]) - self.W_platform
        return e - e[0]


def _tolerances(model: Model, rtol: float, atol_scale: float | None):
    """rtol and atol vectors for the state (delta, v, w).

    atol = rtol * atol_scale * (delta_ref, v_ref) for (delta, v); the work
    quadrature w gets atol = inf so that it never enters the error norm. As
    solve_ivp uses an RMS norm over all components, both tolerances are
    multiplied by sqrt(2/3): the step-size control is then exactly that of
    the two-component system (delta, v) with (rtol, atol).
    """
    d_ref, v_ref = model.reference_scales()
    s = 1.0 if atol_scale is None else float(atol_scale)
    c = math.sqrt(2.0 / 3.0)
    atol = np.array([rtol * s * d_ref * c, rtol * s * v_ref * c, np.inf])
    return rtol * c, atol


def _max_step(model: Model) -> float:
    """Largest step (s): 1/20 of the contact period at delta_ref (keeps the
    explicit method well inside its stability region near equilibria, where
    the error estimate alone lets the step grow to the stability limit), and
    1/20 of the excitation period (no grazing contact skipped unseen)."""
    d_ref, _ = model.reference_scales()
    omega_c = math.sqrt(1.5 * model.K * math.sqrt(d_ref) / model.m)
    h = 2 * math.pi / omega_c / 20
    if model.a != 0.0 and model.omega > 0.0:
        h = min(h, 2 * math.pi / model.omega / 20)
    return h


def _wrap_event(g, direction: int, t0: float, y0: np.ndarray):
    """Terminal event for solve_ivp that cannot fire at the start t0.

    A segment that starts on a surface leaves it on the side opposite to the
    event direction (the resolver made the mode consistent); at t0 the event
    reports a tiny value on the pre-crossing side so that brentq never
    returns t0 and a return to the surface within the first step is found.
    While such a segment is still exactly on the surface (g == 0: it leaves
    it slowly, e.g. quadratically from a turning point, and the first steps
    change delta by less than an ulp) it has not crossed it either: exact
    zeros count as the pre-crossing side too. Without this, a segment
    starting at delta = delta_c in unloading with delta' = 0 re-fired
    "reload" every few 1e-16 s (a false Zeno stop).
    """
    start_on_surface = g(t0, y0) == 0.0

    def event(t, y):
        if start_on_surface:
            value = -direction * 1e-300 if t == t0 else g(t, y)
            return -direction * 1e-300 if value == 0.0 else value
        return g(t, y)
    event.terminal = True
    event.direction = direction
    return event


def _hertz_stiffness(model: Model, mode: int, mem: Memory, rate: float = 0.0):
    """(Kc, p) of a force law F ~ Kc (delta - s)^p at the contact surface s of
    ``mode`` entered or left at the rate |d(delta)/dt| = rate (None if the law
    is smooth there, e.g. the LEPP spring and the linear spring-dashpot):
    Hertz p = 1.5; the published damped forms Kc = K (1 + chi); Tsuji's form
    F ~ alpha_c rate delta^(1/4), p = 1/4."""
    if model.law in ("lepp",) or mode not in (ELASTIC, UNLOAD):
        return None
    if model.law == "damped":
        if model.linear:
            return None
        if model.formula == laws.EXACT:
            return (model.alpha_c * abs(rate), 0.25) if rate != 0.0 else None
        return model.K * (1.0 + model.chi), 1.5
    return (mem.Kbar if mode == UNLOAD else model.K), 1.5


def _singular_step(model: Model, law, rate: float, atol: np.ndarray):
    """Step (s) over which the non-smooth part of a Hertz-type contact is < atol.

    Entering or leaving F = Kc (delta - s)^p (law = (Kc, p)) at a rate
    |delta'| = r, the solution carries the terms (Kc/m) r^p |t - t_s|^(p+2)
    in delta and (Kc/m) r^p |t - t_s|^(p+1) in v that are not smooth at the
    surface time t_s; a polynomial step of length h containing t_s misses them
    by about their size, so h = min over (delta, v) of
    (atol m / (Kc r^p))^(1/(p+2)), (...)^(1/(p+1)).
    """
    Kc, p = law
    r = abs(rate)
    if r == 0.0 or Kc == 0.0:
        return np.inf
    c = model.m / (Kc * r ** p)
    return min((atol[0] * c) ** (1 / (p + 2)), (atol[1] * c) ** (1 / (p + 1)))


def _solve(model, mode, mem, t0, y0, t_end, rtol, atol, max_step, first_step):
    """One solve_ivp call of ``mode`` with its terminal surface events.

    Returns (OdeResult, event kind or None)."""
    surfaces = model.surfaces(mode, mem)
    events = [_wrap_event(g, d, t0, y0) for g, d, _ in surfaces]
    if first_step is not None:
        first_step = min(first_step, max_step, t_end - t0)
    sol = solve_ivp(model.rhs(mode, mem), (t0, t_end), y0, method="DOP853",
                    rtol=rtol, atol=atol, dense_output=True, events=events,
                    max_step=max_step, first_step=first_step)
    if sol.status < 0:
        raise RuntimeError(f"solver failed at t={sol.t[-1]}: {sol.message}")
    kind = None
    if sol.status == 1:
        hits = [(te[0], i) for i, te in enumerate(sol.t_events) if len(te)]
        kind = surfaces[min(hits)[1]][2]
    return sol, kind


def _integrate_segment(model: Model, mode: int, mem: Memory, t0: float,
                       y0: np.ndarray, t_end: float, rtol, atol, max_step):
    """Integrate ``mode`` from t0 until t_end or the first event.

    Hertz-type contacts (F ~ (delta - s)^1.5) are not smooth at the contact
    surface, where the error estimate of DOP853 is unreliable:
    - at an onset the first step is limited to the ``_singular_step``;
    - at a separation the last step before the event is redone with a
      maximal step of a quarter of its length, repeatedly (graded steps),
      until it is shorter than twice the ``_singular_step``.
    Returns (segment, event kind or None, state at the end).
    """
    r0 = model.yC1(t0) - y0[1]
    Kc = _hertz_stiffness(model, mode, mem, r0)
    h1 = None
    if Kc is not None and y0[0] == model.contact_surface(mem):
        if r0 > 0.0:
            h1 = _singular_step(model, Kc, r0, atol)
    sol, kind = _solve(model, mode, mem, t0, y0, t_end, rtol, atol,
                       max_step, h1)
    if sol.t[-1] == t0:                      # event at the very start
        seg = Segment(t0, t0, mode, mem, np.array(y0, float), None,
                      np.array([t0]))
        return seg, kind, np.array(sol.y[:, -1], float)
    ts, interp = list(sol.sol.ts), list(sol.sol.interpolants)
    if kind == "separation" and Kc is not None:
        t_s, y_s = sol.t[-1], sol.y[:, -1]
        h_s = _singular_step(model, Kc, model.yC1(t_s) - y_s[1], atol)
        while kind == "separation" and t_s - ts[-2] > 2 * h_s:
            t_prev = ts[-2]
            y_prev = y0 if t_prev == t0 else sol.sol(t_prev)
            sol, kind = _solve(model, mode, mem, t_prev, y_prev, t_end, rtol,
                               atol, max(h_s, (t_s - t_prev) / 4),
                               h1 if t_prev == t0 else None)
            ts = ts[:-1] + list(sol.sol.ts[1:])
            interp = interp[:-1] + list(sol.sol.interpolants)
            t_s = sol.t[-1]
    t1, y_end = float(sol.t[-1]), np.array(sol.y[:, -1], float)
    seg = Segment(t0, t1, mode, mem, np.array(y0, float),
                  OdeSolution(ts, interp), np.array(ts))
    return seg, kind, y_end


def simulate(params: dict, t_end: float, rtol: float = 1e-10,
             atol_scale: float | None = None, t_eval=None) -> Result:
    """Simulate the hybrid model on [0, t_end] and sample the outputs.

    params: FMU parameter names (defaults as in doc/model.md section 5).
    rtol: relative tolerance of DOP853.
    atol_scale: dimensionless factor (default 1) on the absolute tolerances
        atol = rtol * atol_scale * (delta_ref, v_ref), see ``_tolerances``.
    t_eval: sorted sample times in [0, t_end] (default: all solver steps and
        event times). At an event time the state after the event is reported.
    Raises ZenoError if events accumulate at one instant.
    """
    model = Model(params)
    rtol_used, atol = _tolerances(model, rtol, atol_scale)
    max_step = _max_step(model)

    t = 0.0
    delta, v, mem = model.initial_state()
    mode = model.resolve(t, delta, v, mem)
    y = np.array([delta, v, 0.0])
    segments, events, impact_times = [], [], []
    zeno_anchor, zeno_count = 0.0, 0

    while True:
        seg, kind, y_end = _integrate_segment(model, mode, mem, t, y, t_end,
                                              rtol_used, atol, max_step)
        segments.append(seg)
        if kind is None:
            break
        t = seg.t1
        delta, v, mem = model.snap(kind, t, y_end[0], y_end[1], mem)
        new_mode = model.resolve(t, delta, v, mem)
        y = np.array([delta, v, y_end[2]])
        if t - zeno_anchor > ZENO_WINDOW:
            zeno_anchor, zeno_count = t, 0
        zeno_count += 1
        if zeno_count > ZENO_MAX_EVENTS:
            raise ZenoError(f"more than {ZENO_MAX_EVENTS} events within "
                            f"{ZENO_WINDOW} s at t = {t} (mode {mode}, last "
                            f"event {kind})")
        if new_mode != mode:
            events.append((t, mode, new_mode, kind))
            if mode == FREE:
                impact_times.append(t)
        mode = new_mode
        if t >= t_end:                      # event exactly at the end
            segments.append(Segment(t, t, mode, mem, y.copy()))
            break

    return _sample(model, segments, events, impact_times, t_eval, t_end)


def _sample(model: Model, segments, events, impact_times, t_eval, t_end) -> Result:
    """Evaluate the outputs at t_eval from the segments' dense outputs."""
    if t_eval is None:
        t_eval = np.unique(np.concatenate([s.ts for s in segments]
                                          + [[s.t0] for s in segments]))
    t_eval = np.asarray(t_eval, float)
    if np.any(np.diff(t_eval) < 0) or t_eval[0] < 0 or t_eval[-1] > t_end:
        raise ValueError("t_eval must be sorted and within [0, t_end]")
    n = len(t_eval)
    out = {k: np.zeros(n) for k in ("delta", "v", "F", "delta_c", "delta_f",
                                    "delta_p", "Rbar", "W_plastic", "U",
                                    "W_platform")}
    mode_out = np.zeros(n, int)
    starts = np.array([s.t0 for s in segments])
    # last segment starting at or before t: the state after any event at t
    index = np.searchsorted(starts, t_eval, side="right") - 1
    for i_seg in np.unique(index):
        seg = segments[i_seg]
        sel = np.nonzero(index == i_seg)[0]
        ts = t_eval[sel]
        ys = seg.state(ts)
        if seg.mode == STICK:        # exact sliding motion on delta = delta_c
            ys[0], ys[1] = seg.mem.delta_c, [model.yC1(x) for x in ts]
        F = model.force_fn(seg.mode, seg.mem)
        out["delta"][sel], out["v"][sel], out["W_platform"][sel] = ys
        mode_out[sel] = seg.mode
        for j, tj, dj, vj in zip(sel, ts, ys[0], ys[1]):
            out["F"][j] = max(F(tj, dj, vj), 0.0) if seg.mode != STICK else F(tj, dj, vj)
            (out["U"][j], out["W_plastic"][j], out["delta_c"][j],
             out["delta_f"][j], out["delta_p"][j], out["Rbar"][j]) = \
                model.stored_and_plastic(seg.mode, seg.mem, dj)
    yC = model.yC(t_eval)
    n_imp = np.searchsorted(np.array(impact_times), t_eval, side="right")
    return Result(t=t_eval, y=yC - out["delta"], yC=yC, mode=mode_out,
                  n_impacts=n_imp, events=events,
                  n_impacts_total=len(impact_times), n_segments=len(segments),
                  n_steps=sum(len(s.ts) - 1 for s in segments),
                  params=dict(model.p), **out)
