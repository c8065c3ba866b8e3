#!/usr/bin/python3
"""`skin mc` against MCML 1.2.2 side by side: CPU seconds per 10^6 photons of both, one thread,
the same stack and the same radial grid, alternating in one run (a loaded machine slows both
alike; CPU time, user + system of the child, is less sensitive to the load than wall time).

MCML is not part of the project: build it yourself from its public source (Wang, Jacques & Zheng,
e.g. https://github.com/lhvwang/MCML, V1/mcR5unix/mcmlcode) with `gcc -O3 -march=native -o mcml
*.c -lm`, outside the source tree, and pass its path. Usage (from a build tree):

    bench/mc_vs_mcml.py --skin build/bin/skin --mcml /tmp/mcml/mcml [--photons 100000]
        [--repeat 3] [--preset pale] [--wavelength 650]

Prints one line per run and a summary: the median CPU s per 10^6 photons of each and their ratio,
with both programs' R_d per incident power (MCML's total diffuse reflectance, which counts the
photons beyond its grid too) and its standard error from skin mc.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile


def child_cpu():
    t = os.times()
    return t.children_user + t.children_system


def run_cpu(cmd, cwd):
    """(CPU seconds of the child, its stdout)."""
    c = child_cpu()
    out = subprocess.run(cmd, cwd=cwd, check=True, capture_output=True, text=True).stdout
    return child_cpu() - c, out


def mci(stack, photons, dr_cm, nr):
    """An MCML input file for `stack` (skin mc's JSON: mm, 1/mm) with lengths in cm, 1/cm."""
    lines = ["1.0", "1", "", "out.mco A", str(photons), f"{dr_cm:.6g} {dr_cm:.6g}",
             f"100 {nr} 1", "", str(len(stack["layers"])), f"{stack['eta_above']:.6g}"]
    for layer in stack["layers"]:
        d = layer["thickness_mm"]
        d_cm = 1e8 if d is None or d == "inf" or (isinstance(d, float) and d > 1e30) else d / 10
        lines.append(f"{layer['eta']:.10g} {layer['sigma_a'] * 10:.10g} "
                     f"{layer['sigma_s'] * 10:.10g} {layer['g']:.10g} {d_cm:.10g}")
    lines.append(f"{stack['eta_below']:.6g}")
    return "\n".join(lines) + "\n"


def mcml_rd(path):
    """MCML's diffuse reflectance (per incident power) from its .mco output."""
    with open(path) as f:
        m = re.search(r"^(\S+)\s+#Diffuse reflectance", f.read(), re.M)
    return float(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skin", required=True, help="the skin executable")
    ap.add_argument("--mcml", required=True, help="an MCML 1.2.2 executable (built by you)")
    ap.add_argument("--photons", type=int, default=100000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--preset", default="pale")
    ap.add_argument("--wavelength", type=float, default=650)
    ap.add_argument("--radius-max", type=float, default=10.0, help="[mm], as skin mc's default")
    ap.add_argument("--bins", type=int, default=200)
    a = ap.parse_args()
    skin = os.path.abspath(a.skin)
    mcml = os.path.abspath(a.mcml)
    common = ["mc", "--preset", a.preset, "--wavelength", str(a.wavelength), "--threads", "1",
              "--radius-max", str(a.radius_max), "--bins", str(a.bins), "--format", "json"]
    with tempfile.TemporaryDirectory() as tmp:
        stack = json.loads(subprocess.run([skin, *common, "--photons", "1"], check=True,
                                          capture_output=True, text=True).stdout)
        with open(os.path.join(tmp, "in.mci"), "w") as f:
            f.write(mci(stack, a.photons, a.radius_max / 10 / a.bins, a.bins))
        per_m = 1e6 / a.photons
        times = {"skin mc": [], "MCML": []}
        for k in range(a.repeat):
            cpu, out = run_cpu([skin, *common, "--photons", str(a.photons), "--seed", str(k + 1)],
                               tmp)
            r = json.loads(out)
            times["skin mc"].append(cpu * per_m)
            print(f"run {k + 1}: skin mc {cpu * per_m:7.2f} CPU s/1e6  R_d_incident "
                  f"{r['R_d_incident']:.5f} +- {r['R_d_se'] * (1 - r['R_specular']):.5f}",
                  flush=True)
            cpu, _ = run_cpu([mcml, "in.mci"], tmp)
            times["MCML"].append(cpu * per_m)
            print(f"run {k + 1}: MCML    {cpu * per_m:7.2f} CPU s/1e6  R_d_incident "
                  f"{mcml_rd(os.path.join(tmp, 'out.mco')):.5f}", flush=True)
    s, m = statistics.median(times["skin mc"]), statistics.median(times["MCML"])
    pairs = [b / a for a, b in zip(times["skin mc"], times["MCML"])]
    print(f"median CPU s per 10^6 photons ({a.preset}, {a.wavelength:g} nm, one thread, "
          f"{a.photons} photons x {a.repeat}): skin mc {s:.2f}, MCML {m:.2f}, ratio {m / s:.2f}x "
          f"(run by run {min(pairs):.2f}-{max(pairs):.2f}x); load average "
          f"{os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
