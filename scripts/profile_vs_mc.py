#!/usr/bin/python3
"""Radial profiles of the transport models against the project's Monte Carlo (skin mc).

For each case, runs `skin mc` (radial annuli with standard errors) and `skin layers --solver S
--radius ...` for each model S, averages the model over each annulus (4-point Gauss-Legendre in
r with weight r) and reports, over annuli 0.02-10 mm where the Monte Carlo R(r) is above 1e-6 of
its peak, the largest relative deviation and whether every annulus is within 5 % + 3 SE (the
criterion of issue 15). Usage:
  scripts/profile_vs_mc.py [--skin PATH] [--photons N] [--solvers sfd,accurate,multipole] [--cases a,b]
Prints a Markdown table (docs/accurate-solver.md, section 5).
"""
import argparse
import json
import math
import subprocess
import sys

CASES = {
    # name: (mc arguments, description)
    "half-space n=1.4 g=0.9": (["--layer", "sigma_a=0.1,sigma_s_prime=1,g=0.9"], ""),
    "half-space n=1 g=0": (["--layer", "sigma_a=0.1,sigma_s_prime=1,eta=1,g=0"], ""),
    "slab in air 1 mm": (["--layer", "sigma_a=0.01,sigma_s_prime=1,thickness=1,g=0.9"], ""),
    "dark over bright": (["--layer", "sigma_a=2,sigma_s_prime=2,thickness=0.1,g=0.9",
                          "--layer", "sigma_a=0.01,sigma_s_prime=1,g=0.9"], ""),
    "index steps 1.33/1.5/1.4": (["--layer", "sigma_a=0.05,sigma_s_prime=1.5,thickness=0.2,eta=1.33,g=0.8",
                                  "--layer", "sigma_a=0.2,sigma_s_prime=3,thickness=0.3,eta=1.5,g=0.9",
                                  "--layer", "sigma_a=0.02,sigma_s_prime=1,eta=1.4,g=0.9"], ""),
    "thin top g=0.95": (["--layer", "sigma_a=0.5,sigma_s_prime=3,thickness=0.02,g=0.95",
                         "--layer", "sigma_a=0.03,sigma_s_prime=1.5,g=0.8"], ""),
    "g=0 two layers": (["--layer", "sigma_a=0.3,sigma_s_prime=2,thickness=0.3,g=0",
                        "--layer", "sigma_a=0.02,sigma_s_prime=1,g=0"], ""),
}
for preset in ["caucasian", "african", "pale"]:
    for nm in [450, 650]:
        CASES[f"{preset} {nm} nm"] = (["--preset", preset, "--wavelength", str(nm)], "")

GL4 = [(-0.8611363115940526, 0.3478548451374538), (-0.3399810435848563, 0.6521451548625461),
       (0.3399810435848563, 0.6521451548625461), (0.8611363115940526, 0.3478548451374538)]


def run(cmd):
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def layer_args(mc):
    args = []
    for l in mc["layers"]:
        spec = f"sigma_a={l['sigma_a']!r},sigma_s_prime={l['sigma_s_prime']!r},eta={l['eta']!r},g={l['g']!r}"
        if l["thickness_mm"] is not None:
            spec += f",thickness={l['thickness_mm']!r}"
        args += ["--layer", spec]
    return args + ["--eta-above", repr(mc["eta_above"]), "--eta-below", repr(mc["eta_below"])]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--skin", default="build/bin/skin")
    ap.add_argument("--photons", type=int, default=300000)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--solvers", default="sfd,accurate,multipole")
    ap.add_argument("--cases", default="")
    ap.add_argument("--verbose", action="store_true", help="print every annulus that fails")
    a = ap.parse_args()
    solvers = a.solvers.split(",")
    names = [c for c in CASES if not a.cases or any(s in c for s in a.cases.split(","))]
    print("| case | " + " | ".join(f"{s}: worst (r mm)" for s in solvers) + " | " +
          " | ".join(f"{s} pass" for s in solvers) + " |")
    print("|---" * (1 + 2 * len(solvers)) + "|")
    for name in names:
        # Two runs: fine annuli near the beam, coarse ones to 10 mm.
        rows = []
        for rmax, bins in [(0.5, 50), (10.0, 200)]:
            mc = run([a.skin, "mc", *CASES[name][0], "--photons", str(a.photons), "--bins",
                      str(bins), "--radius-max", str(rmax), "--threads", str(a.threads), "--seed", str(a.seed),
                      "--format", "json"])
            w = rmax / bins
            for r, R, se in zip(mc["profile"]["r_mm"], mc["profile"]["R"], mc["profile"]["R_se"]):
                lo, hi = r - w / 2, r + w / 2
                if rmax == 10.0 and hi <= 0.5:
                    continue
                rows.append((lo, hi, R, se))
        peak = max(R for _, _, R, _ in rows)
        rows = [x for x in rows if x[0] >= 0.02 - 1e-12 and x[1] <= 10 + 1e-9 and x[2] > 1e-6 * peak]
        radii, nodes = [], []
        for lo, hi, _, _ in rows:
            pts = [(0.5 * (lo + hi) + 0.5 * (hi - lo) * x, w) for x, w in GL4]
            nodes.append(pts)
            radii += [p for p, _ in pts]
        order = sorted(set(radii))
        results = {}
        for s in solvers:
            args = [a.skin, "layers", "--solver", s, *layer_args(mc), "--format", "json"]
            for r in order:
                args += ["--radius", repr(r)]
            out = run(args)
            prof = dict(zip(order, out["profile"]["R"] if "profile" in out else out["R"]))
            worst, worst_r, ok = 0.0, 0.0, True
            for (lo, hi, R, se), pts in zip(rows, nodes):
                num = sum(w * p * prof[p] for p, w in pts)
                den = sum(w * p for p, w in pts)
                model = num / den
                dev = model / R - 1 if R > 0 else 0
                if abs(dev) > abs(worst):
                    worst, worst_r = dev, 0.5 * (lo + hi)
                if abs(model - R) > 0.05 * R + 3 * se:
                    ok = False
                    if a.verbose:
                        print(f"  {name} {s}: r {lo:.3f}-{hi:.3f} mm model {model:.4g} mc {R:.4g} "
                              f"+- {se:.2g} ({100 * dev:+.1f} %)", file=sys.stderr)
            results[s] = (worst, worst_r, ok)
        print(f"| {name} | " + " | ".join(f"{100 * results[s][0]:+.1f} % ({results[s][1]:.3g})" for s in solvers)
              + " | " + " | ".join("yes" if results[s][2] else "no" for s in solvers) + " |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
