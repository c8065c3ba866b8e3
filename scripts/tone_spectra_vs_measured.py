#!/usr/bin/env python3
"""How plausible the tone presets' spectra are: each preset's R_d (default solver, 400-700 nm)
against every measured skin spectrum in ../shared/data/skin_spectra (Vrhel et al. 1994 NCSU,
CIE TCS 13 and 15; ../shared/data/PROVENANCE.md) and the NIST set in the checkout's
data/skin_spectra/nist_2017 (Cooksey et al. 2017; sphere measurements with the surface
reflection, so the preset is compared there as rho_s F + (1 - rho_s F) R_d, F the Fresnel
reflectance at normal incidence); prints, per preset, the nearest measured spectrum by RMS over
400-700 nm, its RMS, and the measured spectrum's R at 450 and 650 nm next to the preset's (a
Markdown table for docs/tone-presets.md).

Usage (from the root of a checkout, with the Python module built in build/python):

    PYTHONPATH=build/python /usr/bin/python3 scripts/tone_spectra_vs_measured.py [DATA_DIR]
"""
import csv
import os
import sys

import numpy as np

import spectral_skin as ss


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(row for row in f if not row.startswith("#")))
    header, data = rows[0], np.array([[float(x) if x else np.nan for x in r] for r in rows[1:]])
    return header, data


def measured(data_dir, grid):
    out = {}
    meta = {}
    vr = os.path.join(data_dir, "skin_spectra", "vrhel_ncsu")
    with open(os.path.join(vr, "vrhel_skin_metadata.csv"), newline="") as f:
        for row in csv.DictReader(f):
            meta[row["column"]] = f'{row["ethnicity"]}, {row["tone_note"]}'
    header, data = read_columns(os.path.join(vr, "vrhel_skin_reflectance.csv"))
    for j, name in enumerate(header[1:], 1):
        out[name] = (np.interp(grid, data[:, 0], data[:, j]), meta.get(name, ""))
    header, data = read_columns(os.path.join(data_dir, "skin_spectra", "cie_tcs", "cie_tcs_skin.csv"))
    for j, name in enumerate(header[1:], 1):
        ok = ~np.isnan(data[:, j])  # TCS 15 starts at 380 nm
        out[name] = (np.interp(grid, data[ok, 0], data[ok, j]), "CIE test colour sample")
    nist = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "skin_spectra", "nist_2017")
    header, data = read_columns(os.path.join(nist, "nist_skin_reflectance.csv"))
    for j, name in enumerate(header[1:], 1):
        out[name] = (np.interp(grid, data[:, 0], data[:, j]), "NIST, forearm, with the surface reflection")
    return out


def main():
    data_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join("..", "shared", "data")
    names = [n for n in ss.presets() if n.startswith("monk-") or n.startswith("fitzpatrick-")]
    r = ss.spectrum(names[0])
    grid = np.asarray(r["wavelength_nm"])
    refs = measured(data_dir, grid)
    i450, i650 = np.argmin(abs(grid - 450)), np.argmin(abs(grid - 650))
    print("| preset | nearest measured spectrum | RMS | R(450) preset / measured | R(650) preset / measured |")
    print("|---|---|---:|---|---|")
    for name in names:
        r = ss.spectrum(name)
        R = np.asarray(r["R_d"])
        eta, oil = r["parameters"]["eta"], r["parameters"]["oiliness"]
        s = oil * ((eta - 1) / (eta + 1)) ** 2
        with_surface = s + (1 - s) * R

        def model(k):
            return with_surface if k.startswith("nist_") else R
        rms = {k: float(np.sqrt(np.mean((model(k) - v) ** 2))) for k, (v, _) in refs.items()}
        best = min(rms, key=rms.get)
        v, note = refs[best]
        R = model(best)
        print(f"| {name} | {best} ({note}) | {rms[best]:.3f} | {R[i450]:.3f} / {v[i450]:.3f} | "
              f"{R[i650]:.3f} / {v[i650]:.3f} |")


if __name__ == "__main__":
    main()
