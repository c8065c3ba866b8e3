#!/usr/bin/python3
"""Notebook-style tour of the Python package: a melanin sweep and a spectrum fit.

    python3 examples/melanin_sweep.py [OUTPUT.png]     (default melanin_sweep.png)

Needs spectral_skin (pip install --no-build-isolation . , or PYTHONPATH=build/python) and
matplotlib (Debian: python3-matplotlib).
"""
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt
import numpy as np

import spectral_skin as ss

# %% A melanin sweep: one call, 11 parameter sets, computed on all cores.
melanin = np.geomspace(0.002, 0.5, 11)  # pale to dark skin
s = ss.spectrum("caucasian", melanin=melanin)
print("R_d", s["R_d"].shape, "axes", s["axes"]["R_d"])  # (11, 151) ('melanin', 'wavelength_nm')

# %% A "measurement": the tanned preset's spectrum with 1 % noise, fitted by the model.
truth = ss.spectrum("tanned", lambda_step=5)
rng = np.random.default_rng(1)
measured = truth["R_d"] * (1 + 0.01 * rng.standard_normal(truth["R_d"].shape))
fit = ss.fit_spectrum(truth["wavelength_nm"], measured)
p = fit["parameters"]
print(f"fitted melanin {p['melanin']:.4f} (true {truth['parameters']['melanin']}), "
      f"hemoglobin {p['hemoglobin']:.4f} (true {truth['parameters']['hemoglobin']}), rms {fit['rms']:.4f}")

# %% Plot: the sweep drawn in each skin's own colour, and the fit.
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
for i, m in enumerate(melanin):
    left.plot(s["wavelength_nm"], s["R_d"][i], color=s["color"]["hex"][i], label=f"{m:.3g}")
left.set(xlabel="wavelength [nm]", ylabel="R_d", title="Melanin sweep (caucasian preset)", yscale="log")
left.legend(title="melanin", fontsize="small", ncol=2)
right.plot(truth["wavelength_nm"], measured, ".", color="0.3", label="measured (1 % noise)")
right.plot(fit["fitted"]["wavelength_nm"], fit["fitted"]["R"], color="tab:red",
           label=f"fit: melanin {p['melanin']:.3f}, hemoglobin {p['hemoglobin']:.4f}")
right.set(xlabel="wavelength [nm]", ylabel="reflectance", title="Spectrum fit", ylim=(0, None))
right.legend(fontsize="small")
fig.tight_layout()
out = sys.argv[1] if len(sys.argv) > 1 else "melanin_sweep.png"
fig.savefig(out, dpi=100)
print("wrote", out)
