"""A measured-like rail roughness profile: a seeded random profile whose one-third octave band
spectrum is the rail roughness limit of ISO 3095:2013 (6.2.5, the reference track of the vehicle
noise type test) raised by a chosen number of decibels.

ISO 3095 states the limit as band levels L [dB re 1 um] of the roughness in one-third octave bands
of wavelength (table below, 0.4 m down to 3.15 mm). A band level L means a band rms roughness of
1e-6 * 10**(L/20) m. The profile is a sum of sinusoids: N per band, wavenumbers drawn uniformly in
the band, random phases, each of amplitude r_band * sqrt(2/N) so that the band's rms is r_band.
Wavelengths shorter than `shortest` are left out: they are far shorter than the contact patch
(about 12 mm here) and the wheel bridges them anyway. The profile starts flat (the wheel starts at
rest on a smooth rail) and the roughness fades in with a half-cosine.

The table is written as two columns, x [m] and h [m], x increasing: the format of the contact
FMU's `profile_file`.

examples/vehicle-track/roughness.py writes one from the command line.
"""
import numpy as np

from ..files import replacing

# ISO 3095:2013, 6.2.5: rail roughness limit, one-third octave band centre wavelength [m] ->
# level [dB re 1 um].
ISO3095_LIMIT_DB = {
    0.4: 17.1, 0.315: 15.0, 0.25: 13.0, 0.2: 11.0, 0.16: 9.0, 0.125: 7.0, 0.1: 4.9, 0.08: 2.9,
    0.063: 0.9, 0.05: -1.1, 0.04: -3.2, 0.0315: -5.0, 0.025: -5.6, 0.02: -6.2, 0.016: -6.8,
    0.0125: -7.4, 0.01: -8.0, 0.008: -8.6, 0.0063: -9.2, 0.005: -9.8, 0.004: -10.4, 0.00315: -11.0,
}
BAND_HALF_WIDTH = 2.0 ** (1.0 / 6.0)  # one-third octave: edges at centre * 2**(-+1/6)


def components(level_db=15.0, seed=1, shortest=0.01, per_band=16):
    """Wavenumbers k [rad/m], amplitudes [m], phases [rad] of the sinusoids, and the centre
    wavelength [m] of the band each belongs to."""
    rng = np.random.default_rng(seed)
    k, amp, phase, band = [], [], [], []
    for lam, level in sorted(ISO3095_LIMIT_DB.items(), reverse=True):
        if lam < shortest * (1 - 1e-9):
            continue
        r_band = 1e-6 * 10.0 ** ((level + level_db) / 20.0)
        k_lo, k_hi = 2 * np.pi / (lam * BAND_HALF_WIDTH), 2 * np.pi / (lam / BAND_HALF_WIDTH)
        k.append(rng.uniform(k_lo, k_hi, per_band))
        amp.append(np.full(per_band, r_band * np.sqrt(2.0 / per_band)))
        phase.append(rng.uniform(0.0, 2 * np.pi, per_band))
        band.append(np.full(per_band, lam))
    return np.concatenate(k), np.concatenate(amp), np.concatenate(phase), np.concatenate(band)


def taper(x, flat=1.0, ramp=0.3):
    """0 on [0, flat], a half-cosine up to 1 over the next `ramp` metres, then 1."""
    s = np.clip((x - flat) / ramp, 0.0, 1.0)
    return 0.5 * (1.0 - np.cos(np.pi * s))


def profile(length=6.0, dx=1e-3, level_db=15.0, seed=1, shortest=0.01):
    """x [m] and h [m], sampled every dx."""
    n = int(round(length / dx)) + 1
    x = np.linspace(0.0, (n - 1) * dx, n)
    k, amp, phase, _ = components(level_db, seed, shortest)
    h = np.zeros_like(x)
    for kk, aa, pp in zip(k, amp, phase):  # bounded: one pass per sinusoid
        h += aa * np.cos(kk * x + pp)
    return x, taper(x) * h


def band_levels(x, h, lo=0.01, hi=0.4):
    """One-third octave band levels [dB re 1 um] of a sampled profile (FFT, Hann window), for the
    check that the written profile carries the spectrum it was made from."""
    dx = x[1] - x[0]
    w = np.hanning(len(h))
    H = np.fft.rfft(h * w)
    k = 2 * np.pi * np.fft.rfftfreq(len(h), dx)
    # one-sided power per bin, normalised so that the sum equals the mean square of h
    p = 2.0 * np.abs(H) ** 2 / (np.sum(w ** 2) * len(h))
    out = {}
    for lam in ISO3095_LIMIT_DB:
        if lo <= lam <= hi:
            band = (k >= 2 * np.pi / (lam * BAND_HALF_WIDTH)) & (k < 2 * np.pi / (lam / BAND_HALF_WIDTH))
            out[lam] = 10.0 * np.log10(p[band].sum() / 1e-12)
    return out


def write(path, x, h):
    with replacing(path) as fh:
        np.savetxt(fh, np.column_stack([x, h]), fmt="%.10e")

