"""Independent reference for the rolling constraint yb (paper Fig. 1b), straight from its definition.

A body of radius R rolls over a profile h(x), a table (x_i, h_i) with x increasing, linear between
samples (the profile exists on [x_0, x_last] only, or repeats with period x_last - x_0). The lowest
point of the body, touching the profile without penetrating it, is at

    yb(x) = max over s in the profile with |s - x| <= R of [h(s) + sqrt(R^2 - (x - s)^2)] - R.

This module evaluates that maximum numerically, with no geometry worked out beforehand: the
candidates are the samples inside the window (exact), and on every segment inside the window the
maximum of the concave function h(s) + sqrt(R^2 - (x - s)^2), found by a golden-section search
(vectorised over segments) refined to the last bits. It is written for the tests of the FMU's
profile (fmu-test/test_rolling.py) and the rolling figure, not from the FMU's C code.
"""
import numpy as np

GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def read_table(path):
    """(x, h) of a two-column text file: blank lines and lines starting with '#' skipped, columns
    separated by whitespace, a comma or a semicolon."""
    xs, hs = [], []
    with open(path) as f:
        for line in f:
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            a, b = text.replace(",", " ").replace(";", " ").split()
            xs.append(float(a))
            hs.append(float(b))
    return np.array(xs), np.array(hs)


def _tile(x, h, periodic, copies):
    if not periodic:
        return x, h
    L = x[-1] - x[0]
    xs = [x[:-1] + k * L for k in range(-copies, copies + 1)]
    hs = [h[:-1] for _ in range(-copies, copies + 1)]
    return np.concatenate(xs + [x[-1:] + copies * L]), np.concatenate(hs + [h[-1:]])


def yb(x, h, R, at, periodic=False, iterations=120):
    """yb at the positions `at` (array) for the table (x, h) and radius R."""
    x, h, at = np.asarray(x, float), np.asarray(h, float), np.atleast_1d(np.asarray(at, float))
    if periodic:
        L = x[-1] - x[0]
        at = x[0] + np.mod(at - x[0], L)
        x, h = _tile(x, h, True, int(np.ceil(R / L)) + 1)
    out = np.empty_like(at)
    for i, p in enumerate(at):
        lo, hi = p - R, p + R
        # samples in the window
        inside = (x >= lo) & (x <= hi)
        best = np.max(h[inside] + np.sqrt(np.maximum(R * R - (x[inside] - p) ** 2, 0.0))) if inside.any() else -np.inf
        # segments meeting the window: maximise the concave g(s) on each
        j = np.nonzero((x[1:] > lo) & (x[:-1] < hi))[0]
        if len(j):
            a, b = np.maximum(x[j], lo), np.minimum(x[j + 1], hi)
            slope = (h[j + 1] - h[j]) / (x[j + 1] - x[j])
            x0, h0 = x[j], h[j]

            def g(s):
                return h0 + slope * (s - x0) + np.sqrt(np.maximum(R * R - (s - p) ** 2, 0.0))
            c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
            gc, gd = g(c), g(d)
            for _ in range(iterations):
                left = gc > gd
                b = np.where(left, d, b)
                a = np.where(left, a, c)
                c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
                gc, gd = g(c), g(d)
            best = max(best, float(np.max(np.maximum(g(a), g(b)))))
        out[i] = best - R
    return out


def contact_points(x, h, R, p, tol=1e-9):
    """The points s of the profile the body touches when its lowest point is above p: where
    h(s) + sqrt(R^2 - (p - s)^2) - R comes within tol of yb(p) (sampled on a fine grid)."""
    y = yb(x, h, R, [p])[0]
    s = np.linspace(max(x[0], p - R), min(x[-1], p + R), 200001)
    val = np.interp(s, x, h) + np.sqrt(np.maximum(R * R - (s - p) ** 2, 0.0)) - R
    return s[val >= y - tol]
