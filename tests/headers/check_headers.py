#!/usr/bin/env python3
"""Checks of the public headers (include/skin/**.hpp) that the compiler does not make.

--check timings: no comment holds a timing (a number followed by a unit of time: ms, s, CPU-s,
  min, hours, ...). Measured speeds belong in docs/ (docs/benchmarks.md), where their context
  (machine, date, problem size) is kept, not in the interface.
--check layers: a header of layer L (include/skin/L/) includes from include/skin/ only its own
  layer and the layers L links PUBLIC, directly or through them, as the target_link_libraries
  calls of src/CMakeLists.txt and src/*/CMakeLists.txt give them (docs/architecture.md).
--check namespaces: a header of folder F (include/skin/F/) declares everything inside namespace
  skin::F or a namespace nested in it (skin::exporting for include/skin/export/, as `export` is a
  C++ keyword); nothing at global scope, in skin itself or in another folder's namespace.

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


# The namespace of each folder whose name is not its namespace's.
NAMESPACE_OF_FOLDER = {"export": "exporting"}


def code_only(text):
    """The text with comments, string and character literals and preprocessor lines blanked
    (newlines kept, so offsets still give line numbers)."""
    out = []
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":
            # A preprocessor line, with its backslash continuations.
            j = i
            while True:
                k = text.find("\n", j)
                k = n if k < 0 else k
                if k > 0 and text[k - 1] == "\\" and k < n:
                    j = k + 1
                    continue
                break
            out.append(re.sub(r"[^\n]", " ", text[i:k]))
            i = k
            continue
        if c == "\n":
            at_line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            at_line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "'" and i > 0 and text[i - 1].isalnum():
            out.append(" ")  # a digit separator: 1'000
            i += 1
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (min(j + 1, n) - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


OPEN_NAMESPACE = re.compile(r"\b(?:inline\s+)?namespace\s*((?:\w+\s*::\s*)*(?:inline\s+)?\w+)?\s*\{")


def declared_scopes(text):
    """(line number, namespace path) of each namespace scope that holds a declaration. The path
    is a tuple of names ('' for an anonymous namespace); () is the global scope."""
    code = code_only(text)
    stack = []  # one entry per open brace: a tuple of names for a namespace, None otherwise
    found = []
    i, n = 0, len(code)
    while i < n:
        c = code[i]
        if c.isspace():
            i += 1
            continue
        in_namespace_scope = all(entry is not None for entry in stack)
        m = OPEN_NAMESPACE.match(code, i) if in_namespace_scope else None
        if m:
            names = tuple(re.sub(r"\binline\s+", "", part).strip()
                          for part in (m.group(1) or "").split("::"))
            stack.append(names)
            i = m.end()
            continue
        if c == "{":
            stack.append(None)
        elif c == "}":
            if stack:
                stack.pop()
        elif in_namespace_scope:
            path = tuple(name for entry in stack for name in entry)
            line = code.count("\n", 0, i) + 1
            if not found or found[-1][1] != path:
                found.append((line, path))
            # The rest of this declaration up to its end (';' or its body's '{') is not a new one.
            m_end = re.compile(r"[;{}]").search(code, i)
            if m_end and code[m_end.start()] == ";":
                i = m_end.end()
                continue
            if m_end:
                i = m_end.start()
                continue
            break
        i += 1
    return found


def check_namespaces(root):
    findings = []
    for path in sorted((root / "include" / "skin").rglob("*.hpp")):
        folder = path.relative_to(root / "include" / "skin").parts[0]
        expected = ("skin", NAMESPACE_OF_FOLDER.get(folder, folder))
        reported = set()
        for line, scope in declared_scopes(path.read_text(encoding="utf-8")):
            if scope[:2] == expected or scope in reported:
                continue
            reported.add(scope)
            name = "::".join(part or "(anonymous)" for part in scope) or "the global namespace"
            findings.append(f"{path.relative_to(root)}:{line}: declares in {name}, not in "
                            f"{'::'.join(expected)} (the namespace of include/skin/{folder}/)")
    return findings


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--source", required=True, help="the source tree (holds include/ and src/)")
    ap.add_argument("--check", required=True, choices=["timings", "layers", "namespaces"])
    a = ap.parse_args()
    root = pathlib.Path(a.source).resolve()
    findings = {"timings": check_timings, "layers": check_layers,
                "namespaces": check_namespaces}[a.check](root)
    for f in findings:
        print(f)
    if not findings:
        print(f"public headers: {a.check}: ok")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
