#!/usr/bin/env python3
"""Fit the tone presets (monk-01 ... monk-10) once, offline.

Each target is an 8-bit sRGB swatch. Each preset is the project's own extended colour fit of it,
`skin fit --hex RRGGBB --model extended` (Python: fit_color(hex=..., model="extended")): the
default exact solver (accurate: adding-doubling totals), 400-700 nm every 2 nm, D65, seven free
parameters inside the measured ranges of docs/fit.md ("Priors"), with the weak priors that keep
what colour cannot see near the middle of its range. The other parameters are the defaults.
The committed values are rounded to 4 significant digits; the colour and distance printed are
those of the rounded values.

Usage (from the root of a checkout, with the Python module built in build/python):

    PYTHONPATH=build/python /usr/bin/python3 scripts/fit_tone_presets.py

prints one C++ table row per preset (src/physics/skin_parameters.cpp) and a Markdown table
(docs/tone-presets.md).
"""
import math
import sys

import numpy as np

import spectral_skin as ss

# The Monk Skin Tone scale's ten published sRGB swatches (E. Monk; Google, skintone.google).
MONK = ["f6ede4", "f3e7db", "f7ead0", "eadaba", "d7bd96", "a07e56", "825c43", "604134", "3a312a", "292420"]

# The columns of the C++ table, in its order (the parameter table's; docs/fit.md).
FREE = ["melanin", "melanin_blend", "hemoglobin", "oxygenation", "epidermis_thickness",
        "dermis_scattering_scale", "scattering_scale"]


def model_lab(params):
    """CIELAB (D65) of a parameter set, as `skin color` computes it."""
    return np.array(ss.color("caucasian", solver="accurate", **params)["color"]["lab"])


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
    r = ss.fit_color(hex=target_hex, model="extended")
    assert r["free"] == FREE, r["free"]
    target = np.array(r["target"]["lab"])
    params = {k: float(f"{r['parameters'][k]:.4g}") for k in FREE}
    lab = model_lab(params)
    at_bound = [k for k in FREE if r["at_bound"][k]]
    return params, target, lab, ciede2000(target, lab), at_bound


def main():
    rows = []
    for i, h in enumerate(MONK, 1):
        p, target, lab, de, at_bound = fit(h)
        rows.append((f"monk-{i:02d}", h, p, target, lab, de, at_bound))
        print(f"monk-{i:02d} #{h} dE2000 {de:.3f} at bound: {at_bound or '-'} {p}", file=sys.stderr)
    print("// C++ rows: name, target, dE2000, " + ", ".join(FREE))
    for name, h, p, target, lab, de, _ in rows:
        print(f'    {{"{name}", "{h}", {de:.2f}, ' + ", ".join(f"{p[k]:.4g}" for k in FREE) + "},")
    print()
    print("| preset | target | target L*, a*, b* | C_m | beta_m | C_h | gamma | epidermis [mm] | dermis ratio "
          "| scattering | model L*, a*, b* | dE2000 | at a bound |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---|")
    for name, h, p, target, lab, de, at_bound in rows:
        print(f"| {name} | #{h} | {target[0]:.1f}, {target[1]:.1f}, {target[2]:.1f} | {p['melanin']:.4g} | "
              + " | ".join(f"{p[k]:.3g}" for k in FREE[1:])
              + f" | {lab[0]:.1f}, {lab[1]:.1f}, {lab[2]:.1f} | {de:.2f} | {', '.join(at_bound) or '-'} |")


if __name__ == "__main__":
    main()
