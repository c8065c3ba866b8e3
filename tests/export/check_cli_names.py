#!/usr/bin/python3
"""`skin export` with hostile file names and names, end to end (issue 29): every target given -o
stems with quotes, backslashes, line breaks, markup, the code-injection payload and non-ASCII
text writes files that parse (Python by ast and compile, never run; XML by expat; JSON strictly;
pbrt-v4 by its tokenizer's rules) and refer to each other by the names exactly, and nothing runs;
hostile --name values are refused with one line and nothing written; the default file names
cannot shadow the Python package; a FIFO, a device or - takes the main file alone (no
FILE.fit.json beside /dev/null), and one whose main file names files beside it is refused."""
import ast
import json
import os
import re
import struct
import subprocess
import sys
import tempfile
import threading
import xml.etree.ElementTree as ET
import zlib

skin = os.path.abspath(sys.argv[1])
failures = []
PAYLOAD = 'q"+__import__("os").system("touch PWNED")+"q'
STEMS = [PAYLOAD, "q'+__import__('os').system('touch PWNED')+'q",
         "a\"b'c\\d\ne\rf\tg<h>i&j #k [ l ] $m {n} \u00e9\u6f22\U0001F600\u2028z\\"]


def check(cond, what):
    if not cond:
        failures.append(what)


def run(args, cwd, **kw):
    return subprocess.run([skin, *args], cwd=cwd, capture_output=True, **kw)


def png(path, w, h, rgb):
    raw = b"".join(b"\x00" + bytes(rgb) * w for _ in range(h))

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def pbrt_strings(text):
    """The quoted strings of a pbrt-v4 file, decoded by pbrt-v4's tokenizer's rules (a raw line
    feed ends a string in error; backslash escapes b f n r t \\ ' ")."""
    out, i = [], 0
    while i < len(text):
        c = text[i]
        if c == "#":
            while i < len(text) and text[i] not in "\n\r":
                i += 1
        elif c == '"':
            s, i = "", i + 1
            while text[i] != '"':
                if text[i] == "\n":
                    raise ValueError("unterminated string")
                if text[i] == "\\":
                    i += 1
                    s += {"b": "\b", "f": "\f", "n": "\n", "r": "\r", "t": "\t", "\\": "\\", "'": "'", '"': '"'}[text[i]]
                else:
                    s += text[i]
                i += 1
            out.append(s)
        i += 1
    return out


def strict_json(text):
    def bad(x):
        raise ValueError(f"not JSON: {x}")
    return json.loads(text, parse_constant=bad)


def parse(path, stem, target):
    """Parses one written file; checks the references to the other files hold `stem` exactly."""
    data = open(path, "rb").read()
    name = os.path.basename(path)
    if name.endswith(".py"):
        tree = ast.parse(data, path)
        compile(tree, path, "exec")  # compiled, never run
        values = {n.targets[0].id: n.value.value for n in tree.body if isinstance(n, ast.Assign)
                  and isinstance(n.targets[0], ast.Name) and isinstance(n.value, ast.Constant)}
        check(values.get("NAME") == "spectral_skin", f"{target}: NAME {values.get('NAME')!r}")
        if target == "cycles":
            check(values.get("COLOR_MAP") == stem + ".subsurface_color.png", f"{target}: COLOR_MAP {values.get('COLOR_MAP')!r}")
            check(values.get("RADIUS_MAP") == stem + ".subsurface_radius.exr", f"{target}: RADIUS_MAP")
    elif name.endswith((".mtlx", ".xml")):
        root = ET.fromstring(data)
        files = [e.attrib["value"] for e in root.iter("input") if e.attrib.get("type") == "filename"]
        if target in ("openpbr", "standard-surface"):
            check(files == [stem + ".subsurface_color.png", stem + ".subsurface_radius.exr"], f"{target}: files {files!r}")
    elif name.endswith(".gltf"):
        j = strict_json(data.decode("utf-8"))
        check(j["materials"][0]["name"] == "spectral_skin", f"{target}: material {j['materials'][0]['name']!r}")
    elif name.endswith(".json"):
        j = strict_json(data.decode("utf-8"))
        if name.endswith(".fit.json"):
            here = os.path.dirname(path)  # skin ran there: the names are relative to it
            check(all(os.path.exists(os.path.join(here, f)) for f in j["files"]), f"{target}: a file the report lists is missing")
            check(all(os.path.basename(f).startswith(stem) for f in j["files"]), f"{target}: report files {j['files']!r}")
    elif name.endswith(".pbrt"):
        strings = pbrt_strings(data.decode("utf-8"))
        if target == "pbrt-v4" and ".two-layer" not in name:
            spd = [s for s in strings if s.endswith(".spd")]
            check(spd == [stem + ".sigma_a.spd", stem + ".sigma_s.spd"], f"{target}: spd {spd!r}")


with tempfile.TemporaryDirectory() as d:
    png(os.path.join(d, "albedo.png"), 1, 1, (200, 160, 140))
    r = run(["fit", "--texture", "albedo.png", "--solver", "multipole", "-o", "maps.exr"], d)
    check(r.returncode == 0, f"skin fit --texture: {r.stderr.decode()}")
    maps = os.path.join(d, "maps.exr")
    # Every target `skin export --help` lists ("Target: a, b, ..., or all").
    help_text = " ".join(run(["export", "--help"], d).stdout.decode().split())
    targets = re.search(r"Target: (.*?), or all", help_text).group(1).split(", ")
    ext = {"openpbr": ".mtlx", "standard-surface": ".mtlx", "cycles": ".py", "unreal": ".json", "unity": ".cs",
           "pbrt-v4": ".pbrt", "mitsuba3": ".xml", "realtime": ".json", "profile": ".csv", "gltf": ".gltf"}

    # Hostile -o stems, every target (textures where the target takes them, .spd files for pbrt-v4).
    check(sorted(targets) == sorted(ext), f"targets {targets}: the test knows {sorted(ext)}")
    for t in targets:
        for i, stem in enumerate(STEMS):
            out = os.path.join(d, f"{t}-{i}")
            os.mkdir(out)
            extra = ["--parameter-maps", maps] if t in ("openpbr", "standard-surface", "cycles") else []
            extra += ["--spectra-files"] if t == "pbrt-v4" else []
            r = run(["export", "--target", t, "--solver", "multipole", "-o", stem + ext[t], *extra], out)
            if r.returncode != 0:
                failures.append(f"{t} {stem!r}: exit {r.returncode}: {r.stderr.decode()}")
                continue
            names = os.listdir(out)
            check(stem + ".fit.json" in names, f"{t} {stem!r}: no fit report in {names!r}")
            for n in names:
                try:
                    parse(os.path.join(out, n), stem, t)
                except Exception as e:  # noqa: BLE001 - report which file failed
                    failures.append(f"{t}/{n!r}: {type(e).__name__}: {e}")
            check(not os.path.exists(os.path.join(out, "PWNED")), f"{t} {stem!r}: PWNED")

    # Hostile --name: refused with one line, nothing written.
    for name in [PAYLOAD, "a b", "x\ny", "<x>", "\u00e9t\u00e9", ""]:
        out = tempfile.mkdtemp(dir=d)
        r = run(["export", "--target", "all", "--solver", "multipole", "--name", name, "-o", out], out)
        err = r.stderr.decode()
        # (an empty value is refused by the command line for every option, naming the flag)
        lead = "skin: error: --name: the value is empty" if name == "" else "skin: error: name = '"
        check(r.returncode == 2 and err.startswith(lead) and err.count("\n") == 1,
              f"--name {name!r}: exit {r.returncode}, {err!r}")
        check(os.listdir(out) == [], f"--name {name!r}: wrote {os.listdir(out)}")
    out = tempfile.mkdtemp(dir=d)
    r = run(["export", "--target", "all", "--solver", "multipole", "--name", "_skin", "-o", out], out)
    check(r.returncode == 2 and "leading '_'" in r.stderr.decode() and os.listdir(out) == [],
          f"--name _skin with mitsuba3 among the targets: exit {r.returncode}, {os.listdir(out)}")

    # Default names: NAME.TARGET.EXT, never spectral_skin.py (which would shadow the package).
    out = tempfile.mkdtemp(dir=d)
    for t in ("cycles", "unreal"):
        check(run(["export", "--target", t, "--solver", "multipole"], out).returncode == 0, f"default {t}")
    check(sorted(os.listdir(out)) == ["spectral_skin.cycles.fit.json", "spectral_skin.cycles.py",
                                      "spectral_skin.unreal.fit.json", "spectral_skin.unreal.json",
                                      "spectral_skin.unreal.py"], f"default names {sorted(os.listdir(out))}")

    # Not a regular file: the main file alone, no side file beside it; refused where the main
    # file names its side files.
    out = tempfile.mkdtemp(dir=d)
    fifo = os.path.join(out, "pipe")
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(open(fifo, "rb").read()))
    reader.start()
    r = run(["export", "--target", "realtime", "--solver", "multipole", "-o", fifo], out, timeout=60)
    reader.join(60)
    check(r.returncode == 0 and got and strict_json(got[0].decode())["name"] == "spectral_skin", f"FIFO: exit {r.returncode}")
    check(os.listdir(out) == ["pipe"], f"FIFO: side files {os.listdir(out)}")
    check(b"not written: " + fifo.encode() + b".fit.json" in r.stderr, f"FIFO: not stated: {r.stderr!r}")
    r = run(["export", "--target", "unreal", "--solver", "multipole", "-o", "-"], out)
    check(r.returncode == 0 and strict_json(r.stdout.decode())["name"] == "spectral_skin", "-o -: stdout is not the JSON alone")
    check(os.listdir(out) == ["pipe"], f"-o -: side files {os.listdir(out)}")
    # (Side files a broken build creates in /dev, as root, are removed again.)
    side = ["/dev/null" + s for s in (".fit.json", ".sigma_a.spd", ".sigma_s.spd", ".two-layer.pbrt")]
    before = {f for f in side if os.path.exists(f)}

    def created():
        new = [f for f in side if os.path.exists(f) and f not in before]
        for f in new:
            os.remove(f)
        return new
    r = run(["export", "--target", "realtime", "--solver", "multipole", "-o", "/dev/null"], out)
    check(not created() and r.returncode == 0, "/dev/null: a side file")
    r = run(["export", "--target", "pbrt-v4", "--spectra-files", "--solver", "multipole", "-o", "/dev/null"], out)
    err = r.stderr.decode()
    check(not created() and r.returncode == 2 and err.count("\n") == 1 and
          err.startswith("skin: error: output = '/dev/null' is not a regular file"), f"/dev/null with .spd files: {err!r}")
    check(not os.path.exists("PWNED") and not os.path.exists(os.path.join(d, "PWNED")), "PWNED")

for f in failures:
    print("FAIL", f)
print(f"hostile names: {len(targets)} targets x {len(STEMS)} stems, names, defaults, pipes: {len(failures)} failures")
sys.exit(1 if failures else 0)
