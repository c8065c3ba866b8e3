#!/usr/bin/env python3
"""Fit the tone presets (monk-01 ... monk-10) once, offline.

Each target is an 8-bit sRGB swatch; its CIELAB (D65) is the one `skin fit --hex` reports. The
model colour is `skin color`'s: the default exact solver (accurate: adding-doubling totals),
400-700 nm every 2 nm, D65. Six parameters are free, each inside a range measured on human
skin (docs/tone-presets.md gives the sources):

  melanin               0.0005-0.5  (the fit's default interval)
  melanin_blend         0.3-1       (eumelanin dominates the melanin of every skin type)
  hemoglobin            0.002-0.07  (dermal blood volume fraction)
  epidermis_thickness   0.04-0.15 mm (face and body)
  oxygenation           0.6-0.9
  scattering_scale      0.5-2       (a factor 2 around the paper's eq 8)

Six unknowns and three colour coordinates: the residuals are the CIELAB difference plus a weak
prior (0.3 Lab units across a parameter's whole range) that pulls the directions colour cannot
see to the middle of their ranges (geometric middle for blood and thickness), so that no
parameter runs to a bound unless colour needs it. The other parameters are the defaults.

Usage (from the root of a checkout, with the Python module built in build/python):

    PYTHONPATH=build/python /usr/bin/python3 scripts/fit_tone_presets.py

prints one C++ table row per preset (src/physics/skin_parameters.cpp) and a Markdown table
(docs/tone-presets.md).
"""
import math
import sys

import numpy as np
from scipy.optimize import least_squares

import spectral_skin as ss

# The Monk Skin Tone scale's ten published sRGB swatches (E. Monk; Google, skintone.google).
MONK = ["f6ede4", "f3e7db", "f7ead0", "eadaba", "d7bd96", "a07e56", "825c43", "604134", "3a312a", "292420"]

# name, lower, upper, prior, log-scaled
FREE = [
    ("melanin", 0.0005, 0.5, None, True),
    ("melanin_blend", 0.3, 1.0, 0.7, False),
    ("hemoglobin", 0.002, 0.07, math.sqrt(0.002 * 0.07), True),
    ("epidermis_thickness", 0.04, 0.15, math.sqrt(0.04 * 0.15), True),
    ("oxygenation", 0.6, 0.9, 0.75, False),
    ("scattering_scale", 0.5, 2.0, 1.0, True),
]
PRIOR_WEIGHT = 0.3  # Lab units across a parameter's whole range


def to_u(name, v):
    _, lo, hi, _, log = next(f for f in FREE if f[0] == name)
    return (math.log(v / lo) / math.log(hi / lo)) if log else (v - lo) / (hi - lo)


def from_u(u):
    out = {}
    for (name, lo, hi, _, log), x in zip(FREE, u):
        out[name] = lo * (hi / lo) ** x if log else lo + (hi - lo) * x
    return out


def model_lab(us):
    """CIELAB (D65) of the parameter sets given as rows of normalised coordinates."""
    sets = [from_u(u) for u in us]
    kw = {name: np.array([s[name] for s in sets]) for name, *_ in FREE}
    return np.atleast_2d(ss.color("caucasian", solver="accurate", **kw)["color"]["lab"])


def ciede2000(lab1, lab2, terms=False):
    """CIEDE2000 (Sharma, Wu & Dalal 2005); terms=True: its three weighted differences
    (dL'/S_L, dC'/S_C, dH'/S_H; their squares plus the rotation term add up to its square)."""
    L1, a1, b1 = lab1
    L2, a2, b2 = lab2
    C1, C2 = math.hypot(a1, b1), math.hypot(a2, b2)
    Cm = (C1 + C2) / 2
    G = 0.5 * (1 - math.sqrt(Cm**7 / (Cm**7 + 25**7)))
    a1p, a2p = (1 + G) * a1, (1 + G) * a2
    C1p, C2p = math.hypot(a1p, b1), math.hypot(a2p, b2)
    h1p = math.degrees(math.atan2(b1, a1p)) % 360 if C1p else 0
    h2p = math.degrees(math.atan2(b2, a2p)) % 360 if C2p else 0
    dLp, dCp = L2 - L1, C2p - C1p
    dh = h2p - h1p
    if C1p * C2p == 0:
        dh = 0
    elif dh > 180:
        dh -= 360
    elif dh < -180:
        dh += 360
    dHp = 2 * math.sqrt(C1p * C2p) * math.sin(math.radians(dh / 2))
    Lpm, Cpm = (L1 + L2) / 2, (C1p + C2p) / 2
    if C1p * C2p == 0:
        hpm = h1p + h2p
    elif abs(h1p - h2p) <= 180:
        hpm = (h1p + h2p) / 2
    else:
        hpm = (h1p + h2p + 360) / 2 if h1p + h2p < 360 else (h1p + h2p - 360) / 2
    T = (1 - 0.17 * math.cos(math.radians(hpm - 30)) + 0.24 * math.cos(math.radians(2 * hpm))
         + 0.32 * math.cos(math.radians(3 * hpm + 6)) - 0.20 * math.cos(math.radians(4 * hpm - 63)))
    dtheta = 30 * math.exp(-(((hpm - 275) / 25) ** 2))
    RC = 2 * math.sqrt(Cpm**7 / (Cpm**7 + 25**7))
    SL = 1 + 0.015 * (Lpm - 50) ** 2 / math.sqrt(20 + (Lpm - 50) ** 2)
    SC, SH = 1 + 0.045 * Cpm, 1 + 0.015 * Cpm * T
    RT = -math.sin(math.radians(2 * dtheta)) * RC
    if terms:
        return np.array([dLp / SL, dCp / SC, dHp / SH])
    return math.sqrt((dLp / SL) ** 2 + (dCp / SC) ** 2 + (dHp / SH) ** 2 + RT * (dCp / SC) * (dHp / SH))


def fit(target_hex):
    target = np.array(ss.fit_color(hex=target_hex)["target"]["lab"])
    prior = np.array([to_u(n, p) if p is not None else 0.0 for n, _, _, p, _ in FREE])
    weighted = np.array([0.0 if p is None else PRIOR_WEIGHT for _, _, _, p, _ in FREE])

    def residuals(u):
        return np.concatenate([ciede2000(target, model_lab([u])[0], terms=True), weighted * (u - prior)])

    def jacobian(u):
        h = 1e-5
        us = [u] + [np.where(np.arange(len(u)) == i, np.clip(u[i] + h, 0, 1) if u[i] + h <= 1 else u[i] - h, u)
                    for i in range(len(u))]
        labs = model_lab(us)
        J = np.zeros((3 + len(u), len(u)))
        for i in range(len(u)):
            step = us[i + 1][i] - u[i]
            J[:3, i] = (ciede2000(target, labs[i + 1], terms=True) - ciede2000(target, labs[0], terms=True)) / step
            J[3 + i, i] = weighted[i]
        return J

    best = None
    for start in (0.2, 0.5, 0.8):  # melanin start (normalised, log scale)
        u0 = prior.copy()
        u0[0] = start
        r = least_squares(residuals, u0, jac=jacobian, bounds=(0, 1), xtol=1e-10, ftol=1e-12, gtol=1e-12)
        if best is None or r.cost < best.cost:
            best = r
    # The committed values: 4 significant digits (the colour below is that of the rounded values).
    params = {k: float(f"{v:.4g}") for k, v in from_u(best.x).items()}
    lab = model_lab([[to_u(n, params[n]) for n, *_ in FREE]])[0]
    at_bound = [n + ("=" + ("lower" if x < 0.5 else "upper")) for (n, *_), x in zip(FREE, best.x)
                if x < 1e-4 or x > 1 - 1e-4]
    return params, target, lab, ciede2000(target, lab), at_bound


def main():
    rows = []
    for i, h in enumerate(MONK, 1):
        p, target, lab, de, at_bound = fit(h)
        rows.append((f"monk-{i:02d}", h, p, target, lab, de, at_bound))
        print(f"monk-{i:02d} #{h} dE2000 {de:.3f} at bound: {at_bound or '-'} {p}", file=sys.stderr)
    print("// C++ rows: name, target, dE2000, melanin, melanin_blend, hemoglobin, epidermis_thickness, "
          "oxygenation, scattering_scale")
    for name, h, p, target, lab, de, _ in rows:
        print(f'    {{"{name}", "{h}", {de:.2f}, {p["melanin"]:.4g}, {p["melanin_blend"]:.4g}, {p["hemoglobin"]:.4g}, '
              f'{p["epidermis_thickness"]:.4g}, {p["oxygenation"]:.4g}, {p["scattering_scale"]:.4g}}},')
    print()
    print("| preset | target | target L*, a*, b* | C_m | beta_m | C_h | epidermis [mm] | gamma | scattering "
          "| model L*, a*, b* | dE2000 | at a bound |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---|---:|---|")
    for name, h, p, target, lab, de, at_bound in rows:
        print(f"| {name} | #{h} | {target[0]:.1f}, {target[1]:.1f}, {target[2]:.1f} | {p['melanin']:.4g} | "
              f"{p['melanin_blend']:.3g} | {p['hemoglobin']:.3g} | {p['epidermis_thickness']:.3g} | "
              f"{p['oxygenation']:.3g} | {p['scattering_scale']:.3g} | {lab[0]:.1f}, {lab[1]:.1f}, {lab[2]:.1f} | {de:.2f} | "
              f"{', '.join(at_bound) or '-'} |")


if __name__ == "__main__":
    main()
