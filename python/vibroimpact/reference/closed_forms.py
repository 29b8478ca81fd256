"""Closed forms of the model (doc/model.md; paper eqs. 1-5), written from the equations, not from the
C code: effective properties, the yield limit, Johnson's virgin curve and unloading curve, and the
plastic work after a maximum indentation. The tests compare the FMU with them."""
import numpy as np

# the FMU's default parameters (modelDescription.xml start values)
DEFAULTS = dict(m=407.747, P=40000.0, g=9.81, R1=0.475, R2=0.0, E1=2.1e11, E2=2.1e11, nu1=0.3, nu2=0.3,
                Y=6e8, theta_Y=1.1)


def effective(p):
    """Eq. 1 and 5 (textbook yield formula) for the parameters p over DEFAULTS: E_star, R_star, K
    (Hertz stiffness), F_Y, delta_Y, k_lin = F_Y / delta_Y, W = P + m g, m, theta_Y."""
    q = {**DEFAULTS, **p}
    curv = sum(1 / r for r in (q["R1"], q["R2"]) if r > 0)
    R = 1 / curv
    E = 1 / ((1 - q["nu1"] ** 2) / q["E1"] + (1 - q["nu2"] ** 2) / q["E2"])
    K = 4 / 3 * E * np.sqrt(R)
    FY = np.pi * (3 * np.pi / 4) ** 2 * (q["theta_Y"] * q["Y"]) ** 3 * R ** 2 / E ** 2
    dY = (FY / K) ** (2 / 3)
    return dict(E_star=E, R_star=R, K=K, F_Y=FY, delta_Y=dY, k_lin=FY / dY, W=q["P"] + q["m"] * q["g"], m=q["m"],
                theta_Y=q["theta_Y"])


def load(e, d):
    """Johnson's virgin curve at indentation d: Hertz to delta_Y, eq. 3 beyond."""
    d = np.asarray(d, float)
    k = np.maximum(2 * d / e["delta_Y"] - 1, 1.0)
    return np.where(d <= e["delta_Y"], e["K"] * np.clip(d, 0, None) ** 1.5,
                    e["F_Y"] * k * (1 + np.log(k) / (3 * e["theta_Y"])))


def unload_curve(e, dc, variant):
    """(Rbar, delta_r) of the unloading curve (eq. 4) after a maximum indentation dc; variant 1 the
    paper's unloading, 2 the continuous one."""
    if variant == 1:
        kc = 2 * dc / e["delta_Y"] - 1
        return e["R_star"] * np.sqrt(kc), e["delta_Y"] * np.sqrt(kc)
    Fc = float(load(e, dc))
    ac = np.sqrt(e["R_star"] * (2 * dc - e["delta_Y"]))
    return 4 * e["E_star"] * ac ** 3 / (3 * Fc), 3 * Fc / (4 * e["E_star"] * ac)


def w_plastic_closed_form(e, dc, variant):
    """(loading work, W_plastic) after a maximum indentation dc: the work along the virgin curve (eq. 3,
    closed-form antiderivative) and that minus the elastic energy 2/5 F_unload(dc) delta_r the
    unloading curve returns."""
    k, th3 = 2 * dc / e["delta_Y"] - 1, 3 * e["theta_Y"]
    W_load = 0.4 * e["F_Y"] * e["delta_Y"] + 0.5 * e["F_Y"] * e["delta_Y"] * (
        0.5 * (k * k - 1) + (0.5 * k * k * np.log(k) - 0.25 * (k * k - 1)) / th3)
    Rbar, dr = unload_curve(e, dc, variant)
    return W_load, W_load - 0.4 * 4 / 3 * e["E_star"] * np.sqrt(Rbar) * dr ** 2.5
