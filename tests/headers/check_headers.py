#!/usr/bin/env python3
"""Checks of the public headers (include/skin/**.hpp) that the compiler does not make.

--check timings: no comment holds a timing (a number followed by a unit of time: ms, s, CPU-s,
  min, hours, ...). Measured speeds belong in docs/ (docs/benchmarks.md), where their context
  (machine, date, problem size) is kept, not in the interface.
--check layers: a header of layer L (include/skin/L/) includes from include/skin/ only its own
  layer and the layers L links PUBLIC, directly or through them, as the target_link_libraries
  calls of src/CMakeLists.txt and src/*/CMakeLists.txt give them (docs/architecture.md).

Standard library only. Exit 0 when the check passes, 1 with one line per finding otherwise.
"""
import argparse
import pathlib
import re
import sys

# A number, then a unit of time, then no more letters: "0.35 s", "15.6 CPU-s", "47 s", "6 ms",
# "2 min", "3 hours". "um" (micrometres), "mm", "sr" and "spp" are not units of time.
TIME = re.compile(
    r"(?<![\w.])~?\d+(?:\.\d+)?(?:e[-+]?\d+)?\s*"
    r"(?:CPU[- ]s(?:econds?)?|CPU[- ]min(?:utes?)?|CPU[- ]h(?:ours?)?|ms|us|\u00b5s|ns|s|sec|seconds?|min|minutes?|h|hours?|days?)"
    r"(?![\w-])")


def comments(text):
    """(line number, comment text) of every // and /* */ comment, string literals skipped."""
    out = []
    i, n, line = 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append((line, text[i + 2:j]))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j
            body = text[i + 2:j]
            for k, part in enumerate(body.split("\n")):
                out.append((line + k, part))
            line += body.count("\n")
            i = j + 2
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        else:
            i += 1
    return out


def check_timings(root):
    findings = []
    for path in sorted((root / "include" / "skin").rglob("*.hpp")):
        for line, comment in comments(path.read_text(encoding="utf-8")):
            for m in TIME.finditer(comment):
                findings.append(f"{path.relative_to(root)}:{line}: a timing in a public header: "
                                f"'{m.group(0).strip()}' (move it to docs/benchmarks.md)")
    return findings


LINK = re.compile(r"target_link_libraries\s*\(\s*skin_(\w+)([^)]*)\)", re.S)


def public_links(root):
    """Layer -> the skin layers it links PUBLIC (skin::x or skin_x), from src's CMakeLists."""
    links = {}
    files = [root / "src" / "CMakeLists.txt"] + sorted((root / "src").glob("*/CMakeLists.txt"))
    for f in files:
        text = re.sub(r"#[^\n]*", "", f.read_text(encoding="utf-8"))
        for m in LINK.finditer(text):
            target, public = m.group(1), False
            links.setdefault(target, set())
            for word in m.group(2).split():
                if word in ("PUBLIC", "INTERFACE"):
                    public = True
                elif word == "PRIVATE":
                    public = False
                elif public:
                    dep = re.fullmatch(r"skin(?:::|_)(\w+)", word)
                    if dep and dep.group(1) not in ("warnings", "sanitize"):
                        links[target].add(dep.group(1))
    return links


def closure(links, layer):
    seen, todo = set(), [layer]
    while todo:
        for dep in links.get(todo.pop(), ()):
            if dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return seen


INCLUDE = re.compile(r'^\s*#\s*include\s*"skin/(\w+)/', re.M)


def check_layers(root):
    links = public_links(root)
    findings = []
    for path in sorted((root / "include" / "skin").rglob("*.hpp")):
        layer = path.relative_to(root / "include" / "skin").parts[0]
        if layer not in links:
            findings.append(f"{path.relative_to(root)}: layer '{layer}' has no target skin_{layer} in src/")
            continue
        allowed = closure(links, layer) | {layer}
        for m in INCLUDE.finditer(path.read_text(encoding="utf-8")):
            if m.group(1) not in allowed:
                findings.append(
                    f"{path.relative_to(root)}: includes skin/{m.group(1)}/, which skin_{layer} does not "
                    f"link PUBLIC (it links {', '.join(sorted(allowed - {layer})) or 'nothing'})")
    return findings


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--source", required=True, help="the source tree (holds include/ and src/)")
    ap.add_argument("--check", required=True, choices=["timings", "layers"])
    a = ap.parse_args()
    root = pathlib.Path(a.source).resolve()
    findings = check_timings(root) if a.check == "timings" else check_layers(root)
    for f in findings:
        print(f)
    if not findings:
        print(f"public headers: {a.check}: ok")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
