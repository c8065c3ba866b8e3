#!/usr/bin/python3
"""Independent check of the illuminant tables and of `skin color --illuminant`.

Usage: check_illuminants.py SKIN SOURCE_DIR

Reads the project's data files itself (numpy, no project code) and checks:
  1. illuminant A against its closed form (Planck's law as ISO/CIE 11664-2 writes it);
  2. D50 against the CIE daylight formula S0 + M1 S1 + M2 S2 (data/cie_daylight_basis.csv);
  3. every preset under A: XYZ, CIELAB (relative to A's white) and linear sRGB (Bradford to D65)
     from `skin spectrum`'s R_d, integrated here, against `skin color --illuminant A`, to 1e-6;
  4. the RGB-rendering colour of `skin illuminants --compare` under A, recomputed here.
Exit status 0 when every check passes; the failures are printed.
"""
import csv
import json
import subprocess
import sys

import numpy as np

SKIN, SRC = sys.argv[1], sys.argv[2]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def table(name):
    with open(f"{SRC}/data/{name}") as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    header, body = rows[0], rows[1:]
    cols = {h: np.array([float(r[i]) if r[i] != "" else np.nan for r in body]) for i, h in enumerate(header)}
    return cols


def run(*args):
    out = subprocess.run([SKIN, *args, "--format", "json"], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


ill = table("cie_illuminants.csv")
lam5 = ill["lambda_nm"]

# 1. A: S = 100 (560/l)^5 (exp(c2/(T 560)) - 1) / (exp(c2/(T l)) - 1), c2 = 1.435e-2 m K, T = 2848 K;
# the table has 6 significant digits (relative rounding <= 5e-6).
c2, T = 1.435e7, 2848.0  # [nm K], [K]
planck = 100 * (560 / lam5) ** 5 * np.expm1(c2 / (T * 560)) / np.expm1(c2 / (T * lam5))
err = np.max(np.abs(ill["A"] / planck - 1))
check(err <= 5e-6, f"A vs Planck: max relative error {err:.2e} > 5e-6")
print(f"A vs closed form: max relative difference {err:.2e} (6-digit table)")

# 2. D50 from the daylight basis: T = 5000 K x 1.4388/1.4380, x_D, y_D by the CIE polynomials,
# M1, M2 rounded to 3 decimals as the standard prescribes. The table has 3 decimals.
basis = table("cie_daylight_basis.csv")
assert np.array_equal(basis["lambda_nm"], lam5)
Td = 5000 * 1.4388 / 1.4380
xD = -4.6070e9 / Td**3 + 2.9678e6 / Td**2 + 0.09911e3 / Td + 0.244063
yD = -3.0 * xD**2 + 2.870 * xD - 0.275
M = 0.0241 + 0.2562 * xD - 0.7341 * yD
M1 = round((-1.3515 - 1.7703 * xD + 5.9114 * yD) / M, 3)
M2 = round((0.0300 - 31.4424 * xD + 30.0717 * yD) / M, 3)
d50 = basis["S0"] + M1 * basis["S1"] + M2 * basis["S2"]
err = np.max(np.abs(ill["D50"] - d50))
check(err <= 5e-4 + 1e-9, f"D50 vs S0/S1/S2: max difference {err:.2e} > 5e-4")
print(f"D50 vs daylight formula (M1 = {M1}, M2 = {M2}): max difference {err:.1e} (3-decimal table)")

# 3. Presets under A, integrated here on skin's own wavelength grid (400-700 nm, 2 nm), with A
# from its closed form (which defines it; the 5 nm table interpolated linearly is off by up to
# 0.1 % in the visible).
cmf = table("cie1931_2deg_xyz.csv")
d65 = table("d65.csv")
presets = [p["name"] for p in run("presets")]
SRGB = np.array([[3.2404542, -1.5371385, -0.4985314],
                 [-0.9692660, 1.8760108, 0.0415560],
                 [0.0556434, -0.2040259, 1.0572252]])  # IEC 61966-2-1
BRADFORD = np.array([[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]])


def weights(lam, S):
    w = np.stack([S * np.interp(lam, cmf["lambda_nm"], cmf[k]) for k in ("xbar", "ybar", "zbar")])
    return w / w[1].sum()


def lab(c, white):
    t = c / white
    e, k = 216 / 24389, 24389 / 27
    f = np.where(t > e, np.cbrt(t), (k * t + 16) / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


worst = {"XYZ": 0.0, "lab": 0.0, "srgb": 0.0, "rgb_rendering": 0.0}
compare = {(c["preset"], c["illuminant"]): c for c in run("illuminants", "--compare", "--illuminant", "A")["colors"]}
for p in presets:
    s = run("spectrum", "--preset", p)
    lam, R = np.array(s["wavelength_nm"]), np.array(s["R_d"])
    S_A = 100 * (560 / lam) ** 5 * np.expm1(c2 / (T * 560)) / np.expm1(c2 / (T * lam))
    wA, w65 = weights(lam, S_A), weights(lam, np.interp(lam, d65["lambda_nm"], d65["S"]))
    white_A, white_65 = wA.sum(axis=1), w65.sum(axis=1)
    XYZ = wA @ R
    L = lab(XYZ, white_A)
    cone = BRADFORD @ white_65 / (BRADFORD @ white_A)
    adapt = np.linalg.inv(BRADFORD) @ np.diag(cone) @ BRADFORD
    srgb = SRGB @ (adapt @ XYZ) / (SRGB @ white_65)
    got = run("color", "--preset", p, "--illuminant", "A")
    check(got["illuminant"] == "A", f"{p}: JSON illuminant is {got['illuminant']!r}")
    c = got["color"]
    for key, mine, theirs in (("XYZ", XYZ, c["XYZ"]), ("lab", L, c["lab"]), ("srgb", srgb, c["srgb_linear"])):
        d = np.max(np.abs(np.array(theirs) - mine) / np.maximum(np.abs(mine), 1e-3))
        worst[key] = max(worst[key], d)
        check(d <= 1e-6, f"{p} under A: {key} {theirs} vs {mine.tolist()} (relative {d:.1e})")
    # RGB rendering: the skin's white-balanced linear sRGB under D65 times the light's.
    albedo = SRGB @ (w65 @ R) / (SRGB @ white_65)
    light = SRGB @ white_A / (SRGB @ white_65)
    pixel_xyz = np.linalg.solve(SRGB, (albedo * light) * (SRGB @ white_65))
    mine = lab(pixel_xyz, white_A)
    theirs = np.array(compare[(p, "A")]["rgb_rendering"]["lab"])
    d = np.max(np.abs(theirs - mine))
    worst["rgb_rendering"] = max(worst["rgb_rendering"], d)
    # The project inverts the sRGB matrix through the published 7-digit inverse: 1e-5 in L*a*b*.
    check(d <= 1e-4, f"{p} under A: RGB rendering lab {theirs.tolist()} vs {mine.tolist()}")
    check(np.allclose(compare[(p, "A")]["color"]["lab"], L, rtol=1e-6, atol=1e-6),
          f"{p}: --compare's spectral lab differs from skin color's")

print(f"{len(presets)} presets under A: max relative difference XYZ {worst['XYZ']:.1e}, "
      f"CIELAB {worst['lab']:.1e}, linear sRGB {worst['srgb']:.1e}; RGB rendering CIELAB {worst['rgb_rendering']:.1e}")
sys.exit(1 if failures else 0)
