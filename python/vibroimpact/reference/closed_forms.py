"""Closed forms of the model (doc/model.md; paper eqs. 1-5), written from the equations, not from the
C code: effective properties, the yield limit, Johnson's virgin curve and unloading curves, and the
plastic work after a maximum indentation. The tests compare the FMU with them."""
import numpy as np

from .model import DEFAULTS, derived   # the FMU's default parameters; eqs. 1, 2, 5


def effective(p):
    """The model's derived constants (eqs. 1 and 5) for the parameters p over DEFAULTS (names the
    reference model does not know, such as the FMU's solver settings, are left out): E_star, R_star,
    K (Hertz stiffness), F_Y, delta_Y, k_lin = F_Y / delta_Y, and W = P + m g, m, theta_Y."""
    q = {**DEFAULTS, **{k: v for k, v in p.items() if k in DEFAULTS}}
    return dict(derived(q), W=q["P"] + q["m"] * q["g"], m=q["m"], theta_Y=q["theta_Y"])


def load(e, d):
    """Johnson's virgin curve at indentation d: Hertz to delta_Y, eq. 3 beyond."""
    d = np.asarray(d, float)
    k = np.maximum(2 * d / e["delta_Y"] - 1, 1.0)
    return np.where(d <= e["delta_Y"], e["K"] * np.clip(d, 0, None) ** 1.5,
                    e["F_Y"] * k * (1 + np.log(k) / (3 * e["theta_Y"])))


def unload_curve(e, dc, variant):
    """(Rbar, delta_r) of the unloading curve (eq. 4) after a maximum indentation dc. variant 1: the paper's
    unloading; 2: the continuous one, the Hertz curve through the turning point (F_c = load(dc)) whose
    returned energy 2/5 F_c delta_r is at most the virgin work W_c: delta_r = min(delta_r of variant 3,
    5/2 W_c/F_c), Rbar from F_c = 4/3 E* sqrt(Rbar) delta_r^1.5; 3: the radius-continuous curve (force and
    eq. 3's contact radius a_c continuous, a_c^2 = R* (2 dc - delta_Y)), which variant 2 is wherever it
    returns less than W_c."""
    if variant == 1:
        kc = 2 * dc / e["delta_Y"] - 1
        return e["R_star"] * np.sqrt(kc), e["delta_Y"] * np.sqrt(kc)
    Fc = float(load(e, dc))
    ac = np.sqrt(e["R_star"] * (2 * dc - e["delta_Y"]))
    if variant == 3:
        return 4 * e["E_star"] * ac ** 3 / (3 * Fc), 3 * Fc / (4 * e["E_star"] * ac)
    dr = min(3 * Fc / (4 * e["E_star"] * ac), 2.5 * virgin_work(e, dc) / Fc)
    return (3 * Fc / (4 * e["E_star"] * dr ** 1.5)) ** 2, dr


def virgin_work(e, dc):
    """The work along the virgin curve from 0 to dc >= delta_Y (eq. 3, closed-form antiderivative)."""
    k, th3 = 2 * dc / e["delta_Y"] - 1, 3 * e["theta_Y"]
    return 0.4 * e["F_Y"] * e["delta_Y"] + 0.5 * e["F_Y"] * e["delta_Y"] * (
        0.5 * (k * k - 1) + (0.5 * k * k * np.log(k) - 0.25 * (k * k - 1)) / th3)


def w_plastic_closed_form(e, dc, variant):
    """(loading work, W_plastic) after a maximum indentation dc: the work along the virgin curve and that
    minus the elastic energy 2/5 F_unload(dc) delta_r the unloading curve (variant of unload_curve)
    returns."""
    W_load = virgin_work(e, dc)
    Rbar, dr = unload_curve(e, dc, variant)
    return W_load, W_load - 0.4 * 4 / 3 * e["E_star"] * np.sqrt(Rbar) * dr ** 2.5


def negative_w_plastic(Y, variant, points=20001):
    """Where W_plastic < 0 after a Johnson yield at yield stress Y [Pa] (other parameters the defaults), for
    the paper's unloading curve (variant 1) or the radius-continuous one (variant 3; continuous unloading
    returns the whole loading work there instead): (r_zero, r_min, W_min [J]): W_plastic < 0 for
    delta_c < r_zero delta_Y, most negative, W_min, at delta_c = r_min delta_Y (on a grid of `points` values
    of delta_c in (delta_Y, r_zero delta_Y])."""
    from scipy.optimize import brentq
    e = effective(dict(Y=Y))
    wp = lambda r: w_plastic_closed_form(e, r * e["delta_Y"], variant)[1]  # noqa: E731
    r_zero = brentq(wp, 1.0 + 1e-9 if variant == 1 else 1.5, 50.0, xtol=1e-12)
    grid = np.linspace(1.0 + 1e-6, r_zero, points)
    w = np.array([wp(r) for r in grid])
    i = int(np.argmin(w))
    return r_zero, float(grid[i]), float(w[i])


def restitution_peak(Y, variant, points=4001):
    """The largest restitution of an impact without load after a Johnson yield at yield stress Y [Pa]:
    (e_max, v/v_Y there), e = sqrt(1 - W_plastic/W_c) with W_c = 1/2 m v^2 the virgin work to delta_c and
    1/2 m v_Y^2 = 2/5 F_Y delta_Y; from a grid of delta_c in (delta_Y, 60 delta_Y], refined about its best."""
    from scipy.optimize import minimize_scalar
    e = effective(dict(Y=Y))

    def restitution(r):
        W, Wp = w_plastic_closed_form(e, r * e["delta_Y"], variant)
        return float(np.sqrt(1 - Wp / W))

    grid = np.linspace(1.0 + 1e-9, 60.0, points)
    i = int(np.argmax([restitution(r) for r in grid]))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, points - 1)]
    r = minimize_scalar(lambda r: -restitution(r), bounds=(lo, hi), method="bounded", options=dict(xatol=1e-12)).x
    return restitution(r), impact_speed(Y, r)


def impact_speed(Y, r):
    """v/v_Y of the impact without load that turns at delta_c = r delta_Y (1/2 m v_Y^2 = 2/5 F_Y delta_Y)."""
    e = effective(dict(Y=Y))
    return float(np.sqrt(virgin_work(e, r * e["delta_Y"]) / (0.4 * e["F_Y"] * e["delta_Y"])))


def negative_permanent_set(Y):
    """(r1, r2): continuous unloading's permanent set delta_f is negative for r1 < delta_c/delta_Y < r2 at
    yield stress Y [Pa] (the curve pushes at negative indentation there)."""
    from scipy.optimize import brentq
    e = effective(dict(Y=Y))
    f = lambda r: r - unload_curve(e, r * e["delta_Y"], 2)[1] / e["delta_Y"]  # noqa: E731
    grid = np.linspace(1.0 + 1e-6, 60.0, 6001)
    sign = np.sign([f(r) for r in grid])
    where = np.nonzero(sign[1:] != sign[:-1])[0]
    if len(where) < 2:
        return None
    return (brentq(f, grid[where[0]], grid[where[0] + 1], xtol=1e-12),
            brentq(f, grid[where[-1]], grid[where[-1] + 1], xtol=1e-12))
