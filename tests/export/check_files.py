#!/usr/bin/python3
"""Every file `skin export --target all` writes, for every preset, parses as what it claims to be
(XML, JSON, glTF, Python that compiles, C#/pbrt with balanced brackets, CSV whose table integrates to
the R_d it states), and every fit report is present with the error bounds of docs/export.md."""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

skin = sys.argv[1]
# The paper's presets (no target colour): the tone presets' thin epidermis is solved off the skin
# table (seconds to minutes per export), and the files' form does not depend on the values.
presets = [p["name"] for p in json.loads(subprocess.check_output([skin, "presets", "--format", "json"]))
           if "target_hex" not in p]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def balanced(text, pairs=("()", "[]", "{}")):
    for a, b in pairs:
        if text.count(a) != text.count(b):
            return False
    return text.count('"') % 2 == 0


with tempfile.TemporaryDirectory() as d:
    for preset in presets:
        out = os.path.join(d, preset)
        os.mkdir(out)
        subprocess.check_call([skin, "export", "--target", "all", "--preset", preset, "-o", out],
                              stdout=subprocess.DEVNULL)
        fits = [f for f in os.listdir(out) if f.endswith(".fit.json")]
        check(len(fits) == 10, f"{preset}: {len(fits)} fit reports, expected 10")
        for name in sorted(os.listdir(out)):
            path = os.path.join(out, name)
            text = open(path, "rb").read()
            where = f"{preset}/{name}"
            try:
                if name.endswith((".mtlx", ".xml")):
                    root = ET.fromstring(text)
                    check(root.tag in ("materialx", "scene"), f"{where}: root <{root.tag}>")
                elif name.endswith((".json", ".gltf")):
                    j = json.loads(text)
                    if name.endswith(".gltf"):
                        check(j["asset"]["version"] == "2.0" and len(j["materials"]) == 1, f"{where}: not glTF 2.0")
                    if name.endswith(".fit.json"):
                        check(j["delta_e_2000"] < 2.0, f"{where}: dE {j['delta_e_2000']}")
                        check(all(math.isfinite(v) for v in j["profile_l1"].values()), f"{where}: L1")
                        check(all(os.path.exists(f) for f in j["files"]), f"{where}: files missing")
                elif name.endswith(".py"):
                    compile(text, path, "exec")
                elif name.endswith((".pbrt", ".cs")):
                    check(balanced(text.decode()), f"{where}: unbalanced brackets or quotes")
                elif name.endswith(".csv"):
                    lines = text.decode().splitlines()
                    rows = list(csv.reader(l for l in lines if not l.startswith("#")))
                    r = [float(x[0]) for x in rows[1:]]
                    R = [float(x[1]) for x in rows[1:]]
                    total = sum(math.pi * (R[i] * r[i] + R[i + 1] * r[i + 1]) * (r[i + 1] - r[i])
                                for i in range(len(r) - 1))
                    stated = float(next(l for l in lines if l.startswith("# R_d:")).split(":")[1].split(",")[0])
                    check(abs(total / stated - 1) < 0.02, f"{where}: table integrates to {total}, R_d {stated}")
                elif name.endswith(".exr"):
                    check(text[:4] == b"\x76\x2f\x31\x01", f"{where}: not OpenEXR")
                else:
                    check(False, f"{where}: unexpected file")
            except Exception as e:  # noqa: BLE001 - report which file failed
                failures.append(f"{where}: {e}")
for f in failures:
    print("FAIL", f)
print(f"checked {len(presets)} presets x 10 targets: {len(failures)} failures")
sys.exit(1 if failures else 0)
