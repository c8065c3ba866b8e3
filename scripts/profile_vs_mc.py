#!/usr/bin/python3
"""Radial profiles of the transport models against the project's Monte Carlo (skin mc).

For each case, runs `skin mc` once (annuli of 10 um to 10 mm, with standard errors; beyond 0.5 mm
merged into annuli of 50 um) and `skin layers --solver S --radius ...` for each model S, averages
the model over each annulus (4-point Gauss-Legendre in r with weight r) and reports, over annuli
0.02-10 mm where the Monte Carlo R(r) is above 1e-6 of its peak, the largest relative deviation
and how many annuli are off by more than 5 % + 3 SE (the criterion of issue 15), and R_d against
the Monte Carlo R_d.

Cases: the named ones (CASES below; --cases picks some by substring), with --presets every skin
preset at 400-700 nm every 50 nm (PRESETS; --cases filters them too), or with --random N the first
N stacks of a seeded random family (random_stack(): 1-4 layers, index steps, g 0-0.95, dark tops
over bright layers, thin tops, semi-infinite or finite bottoms; stack i depends on --seed and i
only, so --random 3 gives the first 3 stacks of --random 50).

Solvers: any registered model (sfd, accurate, multipole), and "multipole-shape": the multipole's
profile scaled to the adding-doubling R_d (what the sfd profile would be if it had the multipole's
shape; used to show that a check would catch it).

Reference: `skin mc`, or with --mcml PATH an independent code, MCML 1.2.2 (Wang, Jacques & Zheng
1995; not part of the project: build it from its public source as bench/mc_vs_mcml.py says),
run --mcml-runs times with --photons / runs photons each (its seed is the clock's second, so the
runs start a second apart); its R(r) per annulus is the mean of the runs and its standard error
their spread over sqrt(runs). MCML counts per incident photon in 1/cm^2: divided by 1 - R_specular
and by 100 to be per power that entered in 1/mm^2 like skin mc. Its last annulus holds every photon
beyond the grid and is dropped; a semi-infinite layer is 10^6 m thick.

Photons: --photons N for every case, or with --mc-cpu S per case from a timed pilot run (20000
photons, one thread): the largest of 1, 2, 5 x 10^k photons whose run takes about S CPU-seconds,
between 10^5 and --photons (the count used is in the table).

Usage:
  scripts/profile_vs_mc.py [--skin PATH] [--photons N] [--solvers sfd,accurate,multipole] [--cases a,b]
  scripts/profile_vs_mc.py --random 50 --seed 15 --mc-cpu 15 --photons 20000000 \
      --solvers sfd,multipole,multipole-shape --cache /tmp/sfd-cache --markdown docs/validation/random-stacks.md
  (--random 25 --first 25 runs stacks 25-49 alone, e.g. in a second process; with the same --cache
  a later run of all 50 reuses their profiles)
  scripts/profile_vs_mc.py --presets --photons 5000000 --mc-cpu 60 --solvers accurate,sfd,multipole \
      --markdown docs/validation/preset-profiles.md
  scripts/profile_vs_mc.py --mcml /tmp/mcml/mcml --mcml-runs 4 --photons 1000000 --solvers sfd,accurate,multipole
  scripts/profile_vs_mc.py --random 3 --seed 347 --photons 30000 --max-rse 0.1 --threads 1 \
      --solvers sfd,multipole-shape --check sfd --check-fails multipole-shape   # the CI test (tests/mc)
Prints a Markdown table (docs/validation/accurate-solver-history.md, sections 4 and 5); exit
status 1 when a --check solver fails a case or a --check-fails solver passes every case.
"""
import argparse
import hashlib
import json
import math
import os
import random
import resource
import statistics
import subprocess
import sys
import tempfile
import time

CASES = {
    # name: skin mc arguments
    "half-space n=1.4 g=0.9": ["--layer", "sigma_a=0.1,sigma_s_prime=1,g=0.9"],
    "half-space n=1 g=0": ["--layer", "sigma_a=0.1,sigma_s_prime=1,eta=1,g=0"],
    "slab in air 1 mm": ["--layer", "sigma_a=0.01,sigma_s_prime=1,thickness=1,g=0.9"],
    "dark over bright": ["--layer", "sigma_a=2,sigma_s_prime=2,thickness=0.1,g=0.9",
                         "--layer", "sigma_a=0.01,sigma_s_prime=1,g=0.9"],
    "index steps 1.33/1.5/1.4": ["--layer", "sigma_a=0.05,sigma_s_prime=1.5,thickness=0.2,eta=1.33,g=0.8",
                                 "--layer", "sigma_a=0.2,sigma_s_prime=3,thickness=0.3,eta=1.5,g=0.9",
                                 "--layer", "sigma_a=0.02,sigma_s_prime=1,eta=1.4,g=0.9"],
    "thin top g=0.95": ["--layer", "sigma_a=0.5,sigma_s_prime=3,thickness=0.02,g=0.95",
                        "--layer", "sigma_a=0.03,sigma_s_prime=1.5,g=0.8"],
    "g=0 two layers": ["--layer", "sigma_a=0.3,sigma_s_prime=2,thickness=0.3,g=0",
                       "--layer", "sigma_a=0.02,sigma_s_prime=1,g=0"],
}
for preset in ["caucasian", "asian", "african", "pale"]:
    for nm in [450, 650]:
        CASES[f"{preset} {nm} nm"] = ["--preset", preset, "--wavelength", str(nm)]
# Dark skin's far field at the shortest wavelengths (issue 31).
for preset in ["asian", "african"]:
    CASES[f"{preset} 400 nm"] = ["--preset", preset, "--wavelength", "400"]
# Skin off the accurate model's skin table (another g or dermis scattering: solved, not read).
for preset, nm, flag, value in [("caucasian", 650, "g", "0.95"), ("african", 650, "g", "0.95"),
                                ("african", 450, "g", "0.8"),
                                ("caucasian", 650, "dermis-scattering-scale", "0.25")]:
    CASES[f"{preset} {nm} nm {flag}={value}"] = ["--preset", preset, "--wavelength", str(nm),
                                                f"--{flag}", value]

# Every preset of the paper at 400-700 nm (--presets).
PRESETS = {f"{preset} {nm} nm": ["--preset", preset, "--wavelength", str(nm)]
           for preset in ["caucasian", "asian", "african", "pale", "tanned", "ear"]
           for nm in range(400, 701, 50)}

GL4 = [(-0.8611363115940526, 0.3478548451374538), (-0.3399810435848563, 0.6521451548625461),
       (0.3399810435848563, 0.6521451548625461), (0.8611363115940526, 0.3478548451374538)]
R_MAX, BINS, FINE_MAX, MERGE = 10.0, 1000, 0.5, 5  # one run: 10 um annuli, merged by 5 beyond 0.5 mm
R_LO, R_HI, FLOOR, REL, NSE = 0.02, 10.0, 1e-6, 0.05, 3.0  # the criterion of issue 15


def log_uniform(rng, lo, hi):
    return math.exp(rng.uniform(math.log(lo), math.log(hi)))


def random_stack(seed, i):
    """Stack i of the random family: a list of layer dicts (thickness None = semi-infinite) and
    eta_below. Ranges (1/mm, mm): sigma_s' 0.5-5 and sigma_a 0.005-2 (log-uniform; alpha' 0.2-0.999),
    g 0-0.95, n 1.33-1.55 per layer (so an index step at every interface), under air; 1-4 layers;
    inner layers 0.02-1 mm thick; the last semi-infinite or (half the stacks) 0.2-3 mm over air or
    glass (n 1.5). Every 5th stack (i = 1, 6, ...) has a dark top (alpha' 0.15-0.6, 0.05-0.5 mm) over a
    bright layer (sigma_a 0.005-0.03); every 5th (i = 2, 7, ...) a thin top (0.005-0.05 mm; when
    it is the only layer and drawn semi-infinite it stays a half-space)."""
    rng = random.Random(1000003 * seed + i)
    n = rng.randint(1, 4)
    kind = i % 5
    if kind == 1:
        n = max(n, 2)
    layers = []
    for j in range(n):
        l = {"sigma_s_prime": log_uniform(rng, 0.5, 5.0), "sigma_a": log_uniform(rng, 0.005, 2.0),
             "g": rng.uniform(0.0, 0.95), "eta": rng.uniform(1.33, 1.55),
             "thickness": log_uniform(rng, 0.02, 1.0)}
        if kind == 1 and j == 0:
            alpha = rng.uniform(0.15, 0.6)
            l["sigma_a"] = l["sigma_s_prime"] * (1 - alpha) / alpha
            l["thickness"] = log_uniform(rng, 0.05, 0.5)
        if kind == 1 and j == 1:
            l["sigma_a"] = log_uniform(rng, 0.005, 0.03)
        if kind == 2 and j == 0:
            l["thickness"] = log_uniform(rng, 0.005, 0.05)
        layers.append(l)
    eta_below = 1.0
    if rng.random() < 0.5:
        layers[-1]["thickness"] = None
    else:
        layers[-1]["thickness"] = log_uniform(rng, 0.2, 3.0)
        eta_below = rng.choice([1.0, 1.5])
    if kind == 2 and n == 1 and layers[0]["thickness"] is not None:
        layers[0]["thickness"] = log_uniform(rng, 0.005, 0.05)  # a thin slab
    name = ["random", "dark top", "thin top", "random", "random"][kind]
    return f"#{i} {name}", layers, eta_below


def stack_args(layers, eta_below):
    args = []
    for l in layers:
        spec = f"sigma_a={l['sigma_a']:.6g},sigma_s_prime={l['sigma_s_prime']:.6g},eta={l['eta']:.6g},g={l['g']:.6g}"
        if l["thickness"] is not None:
            spec += f",thickness={l['thickness']:.6g}"
        args += ["--layer", spec]
    return args + ["--eta-below", f"{eta_below:.6g}"]


def stack_text(layers, eta_below):
    parts = []
    for l in layers:
        d = "inf" if l["thickness"] is None else f"{l['thickness']:.3g}"
        parts.append(f"{l['sigma_a']:.3g}/{l['sigma_s_prime']:.3g}/{d} n {l['eta']:.3g} g {l['g']:.2f}")
    below = "" if layers[-1]["thickness"] is None else f" / below n {eta_below:.3g}"
    return " \\| ".join(parts) + below


def run(cmd):
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def cpu_children():
    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


def layer_args(mc):
    args = []
    for l in mc["layers"]:
        spec = f"sigma_a={l['sigma_a']!r},sigma_s_prime={l['sigma_s_prime']!r},eta={l['eta']!r},g={l['g']!r}"
        if l["thickness_mm"] is not None:
            spec += f",thickness={l['thickness_mm']!r}"
        args += ["--layer", spec]
    return args + ["--eta-above", repr(mc["eta_above"]), "--eta-below", repr(mc["eta_below"])]


def choose_photons(a, mc_args):
    """The photon count: --photons, or with --mc-cpu the 1-2-5 step that a pilot run says fits."""
    if not a.mc_cpu:
        return a.photons
    pilot = 20000
    t0 = cpu_children()
    run([a.skin, "mc", *mc_args, "--photons", str(pilot), "--bins", "10", "--radius-max", str(R_MAX),
         "--threads", "1", "--seed", str(a.seed + 1), "--format", "json"])
    per_photon = max(cpu_children() - t0, 1e-3) / pilot
    best = 100000
    for e in range(5, 8):
        for m in (1, 2, 5):
            if m * 10 ** e * per_photon <= a.mc_cpu:
                best = max(best, m * 10 ** e)
    return min(best, a.photons)


def mcml_tools():
    """bench/mc_vs_mcml.py's MCML input writer and R_d reader (one home for MCML's file formats)."""
    import importlib.util
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench", "mc_vs_mcml.py")
    spec = importlib.util.spec_from_file_location("mc_vs_mcml", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def mcml_values(text, flag):
    """The numbers after MCML's line `flag` up to the next blank line."""
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith(flag)) + 1
    out = []
    while i < len(lines) and lines[i].strip():
        out += [float(x) for x in lines[i].split()]
        i += 1
    return out


def run_mcml(a, mc_args, photons):
    """MCML's R(r) in skin mc's JSON layout: the mean of --mcml-runs runs and its standard error."""
    tools = mcml_tools()
    stack = run([a.skin, "mc", *mc_args, "--photons", "1", "--format", "json"])
    per_run = max(1, photons // a.mcml_runs)
    rd, profiles = [], []
    with tempfile.TemporaryDirectory() as tmp:
        procs = []
        for k in range(a.mcml_runs):
            d = os.path.join(tmp, str(k))
            os.makedirs(d)
            with open(os.path.join(d, "in.mci"), "w") as f:
                # the grid of skin mc's runs here plus one annulus for the photons beyond it
                f.write(tools.mci(stack, per_run, R_MAX / BINS / 10, BINS + 1))
            if len(procs) >= a.threads:  # at most --threads at once
                procs.pop(0).wait()
            time.sleep(1.1)  # MCML seeds from the clock's second
            procs.append(subprocess.Popen([os.path.abspath(a.mcml), "in.mci"], cwd=d,
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        for p in procs:
            p.wait()
        for k in range(a.mcml_runs):
            out_mco = os.path.join(tmp, str(k), "out.mco")
            with open(out_mco) as f:
                text = f.read()
            scale = 1 / (1 - stack["R_specular"])
            rd.append(tools.mcml_rd(out_mco) * scale)
            profiles.append([v * scale / 100 for v in mcml_values(text, "Rd_r #")[:BINS]])
    n = len(profiles)
    mean = [statistics.fmean(col) for col in zip(*profiles)]
    se = [statistics.stdev(col) / math.sqrt(n) for col in zip(*profiles)]
    w = R_MAX / BINS
    out = dict(stack)
    out["R_d"] = statistics.fmean(rd)
    out["R_d_se"] = statistics.stdev(rd) / math.sqrt(n)
    out["profile"] = {"r_mm": [(i + 0.5) * w for i in range(BINS)], "R": mean, "R_se": se}
    return out


def annuli(mc):
    """(lo, hi, R, se) of the one run: 10 um annuli to 0.5 mm, then merged by MERGE (area-weighted
    mean; standard errors combined as independent, which slightly overstates them: one photon
    leaves through one annulus only, so the covariances are negative)."""
    w = R_MAX / BINS
    prof = mc["profile"]
    rows, merge = [], []
    for r, R, se in zip(prof["r_mm"], prof["R"], prof["R_se"]):
        lo, hi = r - w / 2, r + w / 2
        if hi <= FINE_MAX + 1e-12:
            rows.append((lo, hi, R, se))
            continue
        merge.append((lo, hi, R, se))
        if len(merge) == MERGE:
            area = [h * h - l * l for l, h, _, _ in merge]
            A = sum(area)
            rows.append((merge[0][0], merge[-1][1], sum(x * m[2] for x, m in zip(area, merge)) / A,
                         math.sqrt(sum((x * m[3]) ** 2 for x, m in zip(area, merge))) / A))
            merge = []
    return rows


def evaluate(a, name, mc_args, solvers):
    photons = a.photons if a.mcml else choose_photons(a, mc_args)
    t0 = cpu_children()
    if a.mcml:
        mc = run_mcml(a, mc_args, photons)
    else:
        mc = run([a.skin, "mc", *mc_args, "--photons", str(photons), "--bins", str(BINS), "--radius-max",
                  str(R_MAX), "--threads", str(a.threads), "--seed", str(a.seed), "--format", "json"])
    mc_cpu = cpu_children() - t0
    rows = annuli(mc)
    peak = max(R for _, _, R, _ in rows)
    rows = [x for x in rows if x[0] >= R_LO - 1e-12 and x[1] <= R_HI + 1e-9]
    # The models at the nodes of every annulus over 0.02-10 mm (so that their output depends on the
    # stack only, and can be cached), the check over those above the floor.
    order = sorted({0.5 * (lo + hi) + 0.5 * (hi - lo) * x for lo, hi, _, _ in rows for x, _ in GL4})
    rows = [x for x in rows if x[2] > FLOOR * peak and (not a.max_rse or x[3] <= a.max_rse * x[2])]
    nodes = [[(0.5 * (lo + hi) + 0.5 * (hi - lo) * x, w) for x, w in GL4] for lo, hi, _, _ in rows]
    outputs, cpu = {}, {}

    def model(s):
        if s not in outputs:
            t = cpu_children()
            args = ["layers", "--solver", s, *layer_args(mc), "--format", "json"]
            for r in order:
                args += ["--radius", repr(r)]
            path = ""
            if a.cache:  # keyed by the command and the binary (its size and time)
                st = os.stat(a.skin)
                key = json.dumps([args, st.st_size, st.st_mtime_ns]).encode()
                path = os.path.join(a.cache, hashlib.sha1(key).hexdigest() + ".json")
            if path and os.path.exists(path):
                with open(path) as f:
                    out = json.load(f)
            else:
                out = run([a.skin, *args])
                out["cpu_seconds"] = cpu_children() - t
                if path:
                    os.makedirs(a.cache, exist_ok=True)
                    with open(path + ".tmp", "w") as f:
                        json.dump(out, f)
                    os.replace(path + ".tmp", path)
            outputs[s] = (out["R_d"], dict(zip(order, out["profile"]["R"])))
            cpu[s] = out["cpu_seconds"]
        return outputs[s]

    results = {}
    for s in solvers:
        if s == "multipole-shape":
            R_d = model("sfd" if "sfd" in solvers else "accurate")[0]
            R_d_mp, prof_mp = model("multipole")
            prof = {r: v * R_d / R_d_mp for r, v in prof_mp.items()}
        else:
            R_d, prof = model(s)
        worst, worst_r, fails, worst_excess = 0.0, 0.0, 0, -1.0
        means = []
        for (lo, hi, R, se), pts in zip(rows, nodes):
            m = sum(w * p * prof[p] for p, w in pts) / sum(w * p for p, w in pts)
            means.append(m)
            dev = m / R - 1 if R > 0 else 0
            if abs(dev) > abs(worst):
                worst, worst_r = dev, 0.5 * (lo + hi)
            worst_excess = max(worst_excess, (abs(m - R) - NSE * se) / R - REL)
            if abs(m - R) > REL * R + NSE * se:
                fails += 1
                if a.verbose:
                    print(f"  {name} {s}: r {lo:.3f}-{hi:.3f} mm model {m:.4g} mc {R:.4g} "
                          f"+- {se:.2g} ({100 * dev:+.1f} %)", file=sys.stderr)
        results[s] = {"worst": worst, "worst_r": worst_r, "fails": fails, "excess": worst_excess, "means": means,
                      "R_d": R_d, "R_d_dev": R_d / mc["R_d"] - 1, "R_d_z": (R_d - mc["R_d"]) / mc["R_d_se"]}
    # Noise of the reference: relative SE of the annuli within 1 mm and beyond.
    rse = [se / R for lo, hi, R, se in rows if R > 0]
    near = [se / R for lo, hi, R, se in rows if R > 0 and hi <= 1.0]
    info = {"photons": photons, "mc_cpu": mc_cpu, "model_cpu": cpu, "annuli": len(rows),
            "R_d": mc["R_d"], "R_d_se": mc["R_d_se"], "rse_near_max": max(near) if near else float("nan"),
            "rse_max": max(rse) if rse else float("nan"),
            "annuli_rows": [(0.5 * (lo + hi), R, se) for lo, hi, R, se in rows]}
    return results, info


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--skin", default="build/bin/skin")
    ap.add_argument("--photons", type=int, default=300000, help="photons per case (the most, with --mc-cpu)")
    ap.add_argument("--mc-cpu", type=float, default=0, help="CPU-seconds aimed at per Monte Carlo run")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--mcml", default="", help="reference: this MCML 1.2.2 executable instead of skin mc")
    ap.add_argument("--mcml-runs", type=int, default=4, help="with --mcml: independent runs (for the SE)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--solvers", default="sfd,accurate,multipole")
    ap.add_argument("--cases", default="")
    ap.add_argument("--presets", action="store_true", help="every preset at 400-700 nm every 50 nm")
    ap.add_argument("--random", type=int, default=0, help="the first N stacks of the random family")
    ap.add_argument("--first", type=int, default=0, help="with --random: start at stack K (to split a run)")
    ap.add_argument("--markdown", default="", help="also write the full table (with stacks) to this file")
    ap.add_argument("--check", default="", help="solvers that must pass every case (exit status 1)")
    ap.add_argument("--check-fails", default="", help="solvers that must fail at least one case")
    ap.add_argument("--max-rse", type=float, default=0,
                    help="check only annuli whose Monte Carlo relative standard error is at most this "
                         "(with few photons per annulus the standard error is itself unreliable)")
    ap.add_argument("--cache", default="", help="keep the models' profiles in this directory and "
                    "reuse them (same stack, radii and skin binary)")
    ap.add_argument("--plot", default="", help="also draw every case's profiles (PNG): Monte Carlo "
                    "with 3 SE bars, each solver as a line")
    ap.add_argument("--verbose", action="store_true", help="print every annulus that fails")
    a = ap.parse_args()
    solvers = a.solvers.split(",")
    if a.random:
        cases = []
        for i in range(a.first, a.first + a.random):
            name, layers, eta_below = random_stack(a.seed, i)
            cases.append((name, stack_args(layers, eta_below), stack_text(layers, eta_below)))
    else:
        named = PRESETS if a.presets else CASES
        cases = [(c, named[c], " ".join(named[c])) for c in named
                 if not a.cases or any(s in c for s in a.cases.split(","))]
    head = ("| case | " + " | ".join(f"{s}: worst (r mm)" for s in solvers) + " | annuli beyond 5 % + 3 SE: "
            + " / ".join(solvers) + " |")
    print(head)
    print("|---" * (2 + len(solvers)) + "|")
    full = []
    for name, mc_args, text in cases:
        res, info = evaluate(a, name, mc_args, solvers)
        print(f"| {name} | " + " | ".join(f"{100 * res[s]['worst']:+.1f} % ({res[s]['worst_r']:.3g})" for s in solvers)
              + " | " + " / ".join(str(res[s]["fails"]) for s in solvers) + " |", flush=True)
        full.append((name, text, res, info))
        if a.markdown:  # after every case, so that a long run can be stopped and still reports
            write_markdown(a, solvers, full, len(cases))
    if a.plot:
        write_plot(a.plot, solvers, full)
    status = 0
    for s in filter(None, a.check.split(",")):
        bad = [n for n, _, r, _ in full if r[s]["fails"] > 0]
        margin = max(r[s]["excess"] for _, _, r, _ in full)
        print(f"check: {s} fails {len(bad)} case(s){': ' + ', '.join(bad) if bad else ''}; largest "
              f"|model - mc| / mc - 3 SE / mc - 5 %: {100 * margin:+.1f} %", file=sys.stderr)
        status = 1 if bad else status
    for s in filter(None, a.check_fails.split(",")):
        fails = [r[s]["fails"] for _, _, r, _ in full]
        print(f"check: {s} fails {sum(1 for f in fails if f)} of {len(fails)} case(s) "
              f"({sum(fails)} annuli; expected: at least one case)", file=sys.stderr)
        status = 1 if not any(fails) else status
    return status


def write_plot(path, solvers, full):
    """One panel per case: the Monte Carlo R(r) per annulus with 3-SE bars, each solver's annulus
    means as a line, on log axes over the annuli checked. With --presets the panels are laid out
    preset by row and wavelength by column."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    n = len(full)
    cols = min(7, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(2.3 * cols, 2.0 * rows), squeeze=False)
    colours = {"accurate": "#0072B2", "sfd": "#009E73", "multipole": "#D55E00",
               "multipole-shape": "#CC79A7"}
    styles = {"accurate": "-", "sfd": "--", "multipole": "-", "multipole-shape": ":"}
    for k, (name, _, res, info) in enumerate(full):
        ax = axes[k // cols][k % cols]
        r = [x[0] for x in info["annuli_rows"]]
        R = [x[1] for x in info["annuli_rows"]]
        se = [min(3 * x[2], 0.999 * x[1]) for x in info["annuli_rows"]]
        ax.errorbar(r, R, yerr=se, fmt="o", ms=1.2, lw=0.5, color="#555555", label="Monte Carlo (3 SE)")
        for s in solvers:
            ax.plot(r, res[s]["means"], styles.get(s, "-"), lw=0.9, color=colours.get(s),
                    label=f"{s}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        fails = " / ".join(str(res[s]["fails"]) for s in solvers)
        ax.set_title(f"{name}\nannuli off: {fails}", fontsize=6.5)
        ax.tick_params(labelsize=5)
    for k in range(n, rows * cols):
        axes[k // cols][k % cols].axis("off")
    handles, labels = axes[0][0].get_legend_handles_labels()
    top = 1 - 0.3 / fig.get_figheight()  # 0.3 inch for the legend
    fig.legend(handles, labels, loc="upper center", ncol=len(labels), fontsize=7, frameon=False)
    fig.supxlabel("r [mm]", fontsize=7)
    fig.supylabel("R(r) [1/mm^2]", fontsize=7)
    fig.tight_layout(rect=(0, 0, 1, top))
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)


def write_markdown(a, solvers, full, total):
    cpu_mc = sum(i["mc_cpu"] for _, _, _, i in full)
    cpu_models = {s: sum(i["model_cpu"].get(s, 0) for _, _, _, i in full) for s in solvers}
    argv, skip = [], False
    for x in sys.argv[1:]:  # the command without --skin PATH (a local binary)
        if skip or x == "--skin":
            skip = not skip
            continue
        argv.append(x)
    done = "" if len(full) == total else f" (the first {len(full)} of the {total} asked for)"
    kind = "random stacks" if a.random else "stacks"
    reference = "MCML 1.2.2" if a.mcml else "Monte Carlo"
    where = ("Stacks: `random_stack()` in that script (ranges in its docstring and in "
             "docs/validation/accurate-solver-history.md, section 5). " if a.random else
             "Stacks: PRESETS in that script (every preset of the paper at 400-700 nm). " if a.presets else
             "Stacks: CASES in that script (docs/validation/accurate-solver-history.md, section 4). ")
    run_text = (f"{a.mcml_runs} runs of MCML 1.2.2 (Wang, Jacques & Zheng 1995, built from its "
                "public source; seeds from the clock), their mean and its standard error, on "
                "annuli of 10 um to 0.5 mm and 50 um to 10 mm" if a.mcml else
                f"one `skin mc` run (seed {a.seed}, annuli of 10 um to 0.5 mm and 50 um to 10 mm)")
    lines = [f"# Radial profiles of {len(full)} {kind} against {reference}{done}", "",
             "Written by `scripts/profile_vs_mc.py " + " ".join(argv) + "` (issue 15). " + where +
             f"Each stack is {run_text} and `skin layers --solver S` "
             "averaged over each annulus. Criterion: every annulus over 0.02-10 mm where the Monte "
             "Carlo R(r) is above 1e-6 of its peak within 5 % + 3 SE; \"worst\" is the largest "
             "relative deviation (at r, mm), \"fail\" the number of annuli beyond 5 % + 3 SE, "
             "\"R_d\" the deviation of R_d from the Monte Carlo R_d in its standard errors.", "",
             f"CPU time: Monte Carlo {cpu_mc / 60:.1f} min, " +
             ", ".join(f"{s} {cpu_models[s] / 60:.1f} min" for s in solvers if cpu_models[s] > 0) +
             " (user + system of the child processes).", "",
             "Stack: sigma_a/sigma_s'/thickness (1/mm, mm; inf = semi-infinite) n g per layer, top "
             "first, under air; photons: of the Monte Carlo run; SE: the largest relative standard "
             "error of the annuli within 1 mm / of all annuli checked.", "",
             "| case | stack | photons | MC R_d | SE (<1 mm / all) | annuli | " +
             " | ".join(f"{s}: worst (r) | fail | R_d (SE)" for s in solvers) + " |",
             "|---|---|---|---|---|---|" + "---|---|---|" * len(solvers)]
    for name, text, res, info in full:
        row = (f"| {name} | {text} | {info['photons']:.0e} | {info['R_d']:.4f} +- {info['R_d_se']:.4f} | "
               f"{100 * info['rse_near_max']:.1f} % / {100 * info['rse_max']:.0f} % | {info['annuli']} |")
        for s in solvers:
            r = res[s]
            row += (f" {100 * r['worst']:+.1f} % ({r['worst_r']:.3g}) | {r['fails']} | "
                    f"{100 * r['R_d_dev']:+.2f} % ({r['R_d_z']:+.1f}) |")
        lines.append(row)
    lines.append("")
    lines.append("Summary: " + "; ".join(
        f"{s} passes {sum(1 for _, _, r, _ in full if r[s]['fails'] == 0)} of {len(full)} stacks "
        f"({sum(r[s]['fails'] for _, _, r, _ in full)} annuli beyond 5 % + 3 SE in all)" for s in solvers) + ".")
    with open(a.markdown + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(a.markdown + ".tmp", a.markdown)


if __name__ == "__main__":
    sys.exit(main())
