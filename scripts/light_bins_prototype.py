#!/usr/bin/env python3
"""Prototype, outside the model: would vessel packaging and a power of wavelength on the reduced
scattering close the light skin-tone bins of the measured-spectra report? (docs/fit.md,
"Validation by skin tone".)

For each Vrhel spectrum whose fitted colour falls in the light or intermediate ITA bin, the
extended spectrum fit (`fit_spectrum(model="extended")`) is the start; then, in Python, the layers'
coefficients come from `spectrum()` and are changed by

  - vessel packaging: the dermis' blood absorption mu times (1 - exp(-2 mu R)) / (2 mu R) for
    vessels of radius R [mm] (fit interval 0.5-50 um);
  - a power of wavelength on sigma_s_prime of both layers, (lambda / 550 nm)^(-db) (db in -1..1);

and R_d is `layers()`' two-layer total at each wavelength (400-700 nm every 10 nm). Both terms
and the nine extended parameters are fitted by scipy's least_squares within the priors' ranges
(no prior cost). Prints each spectrum's RMS before and after. About 2 min per spectrum on one core
(13 spectra).

    PYTHONPATH=build/python /usr/bin/python3 scripts/light_bins_prototype.py [--no-pack] [--no-power] [NAME ...]

Vessel packaging has been part of the model since 2026-12-07 (`blood_vessel_radius`, freed by the
extended spectrum fit). The start fit below therefore includes it; the refit keeps the prototype's
own packaging term and leaves the model's at 0.
"""
import argparse
import csv
import math
import os

import numpy as np
from scipy.optimize import least_squares

import spectral_skin as ss

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "data", "skin_spectra", "vrhel_ncsu", "vrhel_skin_reflectance.csv")
L = np.arange(400, 701, 10.0)
FREE = ["melanin", "melanin_blend", "hemoglobin", "oxygenation", "epidermis_thickness", "dermis_scattering_scale",
        "scattering_scale", "beta_carotene", "epidermal_hemoglobin"]
# The priors' ranges (docs/fit.md) as bounds; beta-carotene and epidermal blood as their fit intervals.
LO = dict(melanin=0.0005, melanin_blend=0.3, hemoglobin=0.002, oxygenation=0.6, epidermis_thickness=0.04,
          dermis_scattering_scale=0.5, scattering_scale=0.5, beta_carotene=0, epidermal_hemoglobin=0)
HI = dict(melanin=0.5, melanin_blend=1, hemoglobin=0.07, oxygenation=0.9, epidermis_thickness=0.15,
          dermis_scattering_scale=2, scattering_scale=2, beta_carotene=100, epidermal_hemoglobin=0.05)


def model(p, radius_mm, db):
    kw = {k: p[k] for k in FREE}
    a = ss.spectrum("caucasian", lambda_min=400, lambda_max=700, lambda_step=10, **kw)
    b = ss.spectrum("caucasian", lambda_min=400, lambda_max=700, lambda_step=10, **dict(kw, hemoglobin=0.0))
    blood = (a["dermis"]["sigma_a"] - b["dermis"]["sigma_a"]) / p["hemoglobin"]  # whole blood's mu_a, 1/mm
    x = 2 * blood * radius_mm
    pack = np.where(x > 1e-9, -np.expm1(-x) / np.maximum(x, 1e-300), 1.0)
    sigma_a_dermis = b["dermis"]["sigma_a"] + p["hemoglobin"] * blood * pack
    out = []
    for i, lam in enumerate(L):
        f = (lam / 550.0) ** (-db)
        e = a["epidermis"]
        r = ss.layers([dict(sigma_a=e["sigma_a"][i], sigma_s_prime=f * e["sigma_s_prime"][i], thickness_mm=e["thickness_mm"]),
                       dict(sigma_a=sigma_a_dermis[i], sigma_s_prime=f * a["dermis"]["sigma_s_prime"][i])])
        out.append(r["R_d"])
    return np.array(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("names", nargs="*", help="Vrhel spectra (default: every light or intermediate one)")
    ap.add_argument("--no-pack", action="store_true")
    ap.add_argument("--no-power", action="store_true")
    args = ap.parse_args()
    rows = list(csv.reader(open(DATA)))
    names = rows[0][1:]
    lam = np.array([float(r[0]) for r in rows[1:]])
    refl = np.array([[float(x) for x in r[1:]] for r in rows[1:]])
    extra = ([("radius", 0.0005, 0.05, 0.02)] if not args.no_pack else []) + \
            ([("db", -1.0, 1.0, 0.0)] if not args.no_power else [])
    for name in args.names or names:
        meas = np.interp(L, lam, refl[:, names.index(name)])
        base = ss.fit_spectrum(list(L), meas, model="extended")
        lab = ss.color("caucasian", **{k: base["parameters"][k] for k in FREE})["color"]["lab"]
        ita = math.degrees(math.atan2(lab[0] - 50, lab[2]))
        if not args.names and not 28 < ita <= 55:
            continue
        keys = FREE + [k for k, *_ in extra]
        lo = np.array([LO[k] for k in FREE] + [e[1] for e in extra])
        hi = np.array([HI[k] for k in FREE] + [e[2] for e in extra])
        x0 = np.clip(np.array([base["parameters"][k] for k in FREE] + [e[3] for e in extra]), lo + 1e-9, hi - 1e-9)

        def residuals(x):
            p = dict(zip(keys, x))
            return model(p, p.get("radius", 0.0), p.get("db", 0.0)) - meas

        r = least_squares(residuals, x0, bounds=(lo, hi), diff_step=1e-3, max_nfev=80)
        added = " ".join(f"{k} {v:.4g}" for k, v in zip(keys[len(FREE):], r.x[len(FREE):]))
        print(f"{name} ITA {ita:.1f}: extended {base['rms']:.5f} -> {math.sqrt(np.mean(r.fun ** 2)):.5f} {added}", flush=True)


if __name__ == "__main__":
    main()
