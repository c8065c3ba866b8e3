#!/usr/bin/python3
"""README.md and the docs pages tell the truth: their links resolve, and the commands they show
give the output they show.

Usage: check_readme.py --skin build/bin/skin [--page README.md --page docs/tour.md ...]
                       [--shared-data ../shared/data] [--only SUBSTRING]
       check_readme.py --links-only [--page FILE ...]

Pages: --page, repeatable (--readme is the same option); by default README.md and the pages moved
out of it: docs/tour.md (the full tour of the command line), docs/hardening.md,
docs/benchmarks.md, docs/limits.md and docs/layout.md.

Links, in every page: each relative link target ([text](target), ![alt](target), [name]: target,
src="..." and href="..."; outside code blocks and `code`) must exist, relative to the page's
folder; a #fragment must be a heading of the page it points to (GitHub's anchors: lower case,
punctuation other than - and _ dropped, spaces as -) . Links with a scheme (https:, mailto:) are
not followed. Every `bash scripts/NAME` line of a ```sh block must name a script that exists, and
README.md must keep its section "Two commands" with `bash scripts/setup.sh` and
`bash scripts/test.sh`. --links-only checks these alone (no --skin needed).

Commands: every ```text block of every page that holds lines starting with "$ ". Such a line
is a command (a trailing backslash continues it on the next line); the lines after it, up to the
next command or the end of the block, are its output as the page shows it. Each command runs in
bash, in a fresh temporary directory, with the directory of --skin first on PATH, stdout on a
pseudo-terminal (so that the default format is the one a reader at a terminal gets) and stderr on
a pipe (so that no progress bar is drawn); the output compared is stdout followed by stderr.

Comparison, line by line, a line split into numbers and the text between them:
  - text exactly, except that runs of spaces count as one and trailing spaces are ignored;
  - a number equals the page's within one unit of its last printed digit (0.3302 allows
    +-0.0001, 1.77e-05 allows +-1e-07) or 1e-10 relative, whichever is larger; integers (no
    point, no exponent) exactly;
  - a number written with a tilde, "~2.9", is a value that legitimately varies (wall time,
    samples/s): any number matches it. This is the only marker; the reader sees "about 2.9";
  - a line "..." (alone, any indent) skips any number of lines, including none;
  - an output whose first line starts with "{" is a JSON object and is compared as a subset:
    ", ..." in it stands for keys left out; the command's output must be one JSON object that
    has the keys shown, with numbers compared as above.
  - "$ echo $?" is not run: its output is the exit code of the command before it. Any other
    command must exit with 0.

Files the pages name (vrhel_skin_reflectance.csv, Map-COL.jpg, examples/) are linked into the
temporary directory from --shared-data and the source tree; a command that needs a file that is
absent is skipped and reported as skipped. Exit code 0 if every link resolves and every command
that ran matched, 1 if not; the report names the page and line, the command, and the first line
that differs.
"""

import argparse
import json
import os
import pty
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import threading
import time

NUMBER = re.compile(r"(?<![\w#.~])(~?)([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(?![\w.])")

# Files a page's command may name: name in the command -> path relative to the shared data.
SHARED_FILES = {
    "vrhel_skin_reflectance.csv": "skin_spectra/vrhel_ncsu/vrhel_skin_reflectance.csv",
    "Map-COL.jpg": "meshes/LeePerrySmith/Map-COL.jpg",
}
# examples/head.json reads the head mesh and its texture from ../../shared/data.
HEAD_MESH = "meshes/LeePerrySmith/LeePerrySmith.glb"


class Command:
    def __init__(self, line_no, text):
        self.line_no = line_no  # the page's line of the "$ "
        self.text = text
        self.expected = []  # (the page's line number, text)


def parse_readme(path):
    """The commands of the ```text blocks, in order."""
    commands = []
    in_block = False
    current = None
    continuing = False
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for i, line in enumerate(lines, start=1):
        if line.startswith("```"):
            in_block = line.strip() == "```text" if not in_block else False
            current, continuing = None, False
            continue
        if not in_block:
            continue
        if continuing:
            current.text += "\n" + line
            continuing = line.endswith("\\")
            continue
        if line.startswith("$ "):
            current = Command(i, line[2:])
            commands.append(current)
            continuing = line.endswith("\\")
        elif current is not None:
            current.expected.append((i, line))
    for c in commands:
        while c.expected and not c.expected[-1][1].strip():
            c.expected.pop()
    return commands


# Pages checked by default, relative to the source tree: the README and the pages moved out of it.
DEFAULT_PAGES = ["README.md", "docs/tour.md", "docs/hardening.md", "docs/benchmarks.md",
                 "docs/limits.md", "docs/layout.md"]
# The README's two set-up commands (scripts/setup.sh and scripts/test.sh name themselves so).
TWO_COMMANDS_HEADING = "## Two commands"
TWO_COMMANDS = ["bash scripts/setup.sh", "bash scripts/test.sh"]

LINK_PATTERNS = [
    re.compile(r"\]\(\s*<?([^)\s>]*)"),                     # [text](target), ![alt](target)
    re.compile(r"^\s*\[[^\]]+\]:\s*<?([^\s>]+)", re.M),       # [name]: target
    re.compile(r"""\b(?:src|href)\s*=\s*["']([^"']*)["']"""),  # <img src="...">, <a href="...">
]
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def prose_lines(text):
    """[(line number, line)] outside fenced code blocks, with `code` spans blanked."""
    out, fence = [], None
    for i, line in enumerate(text.split("\n"), start=1):
        stripped = line.lstrip()
        if fence is None and (stripped.startswith("```") or stripped.startswith("~~~")):
            fence = stripped[:3]
            continue
        if fence is not None:
            if stripped.startswith(fence):
                fence = None
            continue
        out.append((i, re.sub(r"(`+)(.+?)\1", lambda m: " " * len(m.group(0)), line)))
    return out


def heading_anchor(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip())  # links: their text
    text = re.sub(r"[^\w\- ]", "", text.lower())
    return text.replace(" ", "-")


_anchors = {}


def anchors(path):
    """The anchors of a Markdown file's headings (a repeated heading gets -1, -2, ...)."""
    if path not in _anchors:
        found, seen = set(), {}
        with open(path, encoding="utf-8") as f:
            text = f.read()
        fence = None
        for line in text.split("\n"):
            stripped = line.lstrip()
            if fence is None and (stripped.startswith("```") or stripped.startswith("~~~")):
                fence = stripped[:3]
                continue
            if fence is not None:
                if stripped.startswith(fence):
                    fence = None
                continue
            m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                a = heading_anchor(m.group(1))
                n = seen.get(a, 0)
                seen[a] = n + 1
                found.add(a if n == 0 else f"{a}-{n}")
        for m in re.finditer(r"""<a\s+(?:name|id)\s*=\s*["']([^"']+)["']""", text):
            found.add(m.group(1))
        _anchors[path] = found
    return _anchors[path]


def check_links(page, shown, source):
    """Problems with the page's relative links, its sh blocks' scripts (relative to `source`, the
    checkout the commands run in) and (README.md) its two commands: a list of "page:line: ..."
    lines. `shown`: the page's name in messages."""
    problems = []
    here = os.path.dirname(os.path.abspath(page))
    with open(page, encoding="utf-8") as f:
        text = f.read()
    for line_no, line in prose_lines(text):
        for pattern in LINK_PATTERNS:
            for m in pattern.finditer(line):
                target = m.group(1)
                if not target or SCHEME.match(target):
                    if not target:
                        problems.append(f"{shown}:{line_no}: empty link target")
                    continue
                path, _, fragment = target.partition("#")
                full = os.path.normpath(os.path.join(here, path)) if path else os.path.abspath(page)
                if not os.path.exists(full):
                    problems.append(f"{shown}:{line_no}: link to {target}: {path} does not exist")
                    continue
                if fragment:
                    if not full.endswith(".md") or os.path.isdir(full):
                        problems.append(f"{shown}:{line_no}: link to {target}: an anchor into a "
                                        "file that is not Markdown")
                    elif fragment not in anchors(full):
                        problems.append(f"{shown}:{line_no}: link to {target}: no heading "
                                        f"#{fragment} in {os.path.relpath(full, here)}")
    # Scripts the ```sh blocks run (from the top of the checkout).
    root = source
    in_sh, sh_lines = False, []
    for i, line in enumerate(text.split("\n"), start=1):
        if line.startswith("```"):
            in_sh = line.strip() == "```sh" if not in_sh else False
            continue
        if in_sh:
            sh_lines.append((i, line))
            m = re.match(r"\s*bash\s+(\S+)", line)
            if m and not os.path.isfile(os.path.join(root, m.group(1))):
                problems.append(f"{shown}:{i}: `bash {m.group(1)}`: no such script")
    if os.path.abspath(page) == os.path.join(os.path.abspath(source), "README.md"):
        start = text.find("\n" + TWO_COMMANDS_HEADING)
        if start < 0:
            problems.append(f"{shown}: the section {TWO_COMMANDS_HEADING!r} is missing")
        else:
            section = text[start + 1:]
            nxt = re.search(r"^## ", section[3:], re.M)
            section = section[:nxt.start() + 3] if nxt else section
            block = re.search(r"^```sh\n(.*?)^```", section, re.M | re.S)
            shown_commands = [l.split("#")[0].strip() for l in (block.group(1) if block else "").split("\n")]
            shown_commands = [c for c in shown_commands if c]
            if shown_commands != TWO_COMMANDS:
                problems.append(f"{shown}: the ```sh block of {TWO_COMMANDS_HEADING!r} runs "
                                f"{shown_commands}, not {TWO_COMMANDS}")
    return problems


def last_digit_unit(s):
    """One unit in the last printed digit of a number as written; 0 for an integer."""
    mantissa, _, exponent = s.lower().partition("e")
    if "." not in mantissa and not exponent:
        return 0.0
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 10.0 ** (-decimals + (int(exponent) if exponent else 0))


def numbers_match(want, got):
    """want: the page's number as text; got: the output's."""
    w, g = float(want), float(got)
    tol = max(last_digit_unit(want), 1e-10 * abs(w))
    return abs(w - g) <= tol * (1 + 1e-9)


def split(line):
    """[(kind, text)] with kind 'n' (number), '~' (varying number) or 't' (text)."""
    parts, pos = [], 0
    for m in NUMBER.finditer(line):
        if m.start() > pos:
            parts.append(("t", line[pos:m.start()]))
        parts.append(("~" if m.group(1) else "n", m.group(2)))
        pos = m.end()
    if pos < len(line):
        parts.append(("t", line[pos:]))
    norm = []
    for kind, text in parts:
        if kind == "t":
            text = re.sub(r"\s+", " ", text)
            if norm and norm[-1][0] == "t":
                norm[-1] = ("t", norm[-1][1] + text)
                continue
        norm.append((kind, text))
    if norm and norm[-1][0] == "t":
        norm[-1] = ("t", norm[-1][1].rstrip())
        if not norm[-1][1]:
            norm.pop()
    if norm and norm[0][0] == "t":
        norm[0] = ("t", norm[0][1].lstrip())
        if not norm[0][1]:
            norm.pop(0)
    return norm


def line_matches(want, got):
    a, b = split(want), split(got)
    if len(a) != len(b):
        return False
    for (ka, ta), (kb, tb) in zip(a, b):
        if ka == "t":
            if kb != "t" or ta != tb:
                return False
        elif kb != "n":
            return False
        elif ka == "n" and not numbers_match(ta, tb):
            return False
    return True


def match_lines(expected, actual):
    """None if the output matches, else (page line number or None, page text, output line
    index or None): the first place that differs. '...' skips any number of lines."""
    memo = {}

    def go(i, j):
        key = (i, j)
        if key in memo:
            return memo[key]
        if i == len(expected):
            result = None if j == len(actual) else (None, "(end of the page's output)", j)
        elif expected[i][1].strip() == "...":
            result = None
            first = None
            for k in range(j, len(actual) + 1):
                r = go(i + 1, k)
                if r is None:
                    result = None
                    break
                first = first or r
            else:
                result = first
        elif j < len(actual) and line_matches(expected[i][1], actual[j]):
            result = go(i + 1, j + 1)
        else:
            result = (expected[i][0], expected[i][1], j if j < len(actual) else None)
        memo[key] = result
        return result

    sys.setrecursionlimit(max(10000, 4 * (len(expected) + len(actual))))
    return go(0, 0)


class Text(str):
    """A JSON number kept as it was written (its precision sets the tolerance)."""


def parse_json_pattern(text):
    cleaned = re.sub(r",\s*\.\.\.", "", text)
    cleaned = re.sub(r"\.\.\.\s*,?", "", cleaned)
    return json.loads(cleaned, parse_float=Text, parse_int=Text)


def json_subset(want, got, path="$"):
    """None if every key of want is in got with an equal value, else a description."""
    if isinstance(want, dict):
        if not isinstance(got, dict):
            return f"{path}: expected an object, got {json.dumps(got)[:80]}"
        for k, v in want.items():
            if k not in got:
                return f"{path}: key {k!r} missing (keys: {', '.join(got)})"
            r = json_subset(v, got[k], f"{path}.{k}")
            if r:
                return r
        return None
    if isinstance(want, list):
        if not isinstance(got, list) or len(got) < len(want):
            return f"{path}: expected a list of at least {len(want)}, got {json.dumps(got)[:80]}"
        for n, (a, b) in enumerate(zip(want, got)):
            r = json_subset(a, b, f"{path}[{n}]")
            if r:
                return r
        return None
    if isinstance(want, Text):
        if isinstance(got, bool) or not isinstance(got, (int, float)) or not numbers_match(want, repr(got)):
            return f"{path}: page {want}, output {json.dumps(got)}"
        return None
    if want != got:
        return f"{path}: page {json.dumps(want)}, output {json.dumps(got)}"
    return None


def run(command, cwd, path_dir, timeout):
    """(exit code, stdout + stderr lines, wall seconds, CPU seconds) with stdout on a
    pseudo-terminal."""
    master, slave = pty.openpty()
    env = dict(os.environ, PATH=path_dir + os.pathsep + os.environ.get("PATH", ""), COLUMNS="100")
    start = time.monotonic()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.Popen(["bash", "-c", command], cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                            stdout=slave, stderr=subprocess.PIPE, close_fds=True)
    os.close(slave)
    chunks, err = [], []
    reader = threading.Thread(target=lambda: err.append(proc.stderr.read()))
    reader.start()
    while True:
        try:
            data = os.read(master, 65536)
        except OSError:  # EIO: every writer closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    os.close(master)
    try:
        code = proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        code = proc.wait()
    reader.join()
    seconds = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    out = b"".join(chunks).decode("utf-8", "replace").replace("\r\n", "\n")
    text = out + err[0].decode("utf-8", "replace")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    return code, lines, seconds, cpu


def needed_files(command, shared):
    """Files the command names that are missing, and the links to make."""
    missing, links = [], {}
    for name, rel in SHARED_FILES.items():
        if name in command:
            src = os.path.join(shared, rel)
            (links.__setitem__(name, src) if os.path.exists(src) else missing.append(src))
    # `skin figure` renders on the head mesh found in ../shared/data (spheres without it).
    if "examples/head" in command or "skin figure" in command:
        mesh = os.path.join(shared, HEAD_MESH)
        if not os.path.exists(mesh):
            missing.append(mesh)
    return missing, links


def check_commands(page, shown_page, source, skin_dir, shared, args):
    """Runs the commands of the page's ```text blocks and compares: (failures, skipped, number
    run, CPU seconds)."""
    commands = parse_readme(page)
    failures, skipped, ran, total_cpu = [], [], 0, 0.0
    previous_code, previous_text = None, ""
    for c in commands:
        where = f"{shown_page}:{c.line_no}"
        if c.text.strip() == "echo $?":
            if previous_code is None:
                continue
            want = "\n".join(t for _, t in c.expected).strip()
            if want != str(previous_code):
                failures.append(f"{where}: `echo $?` after `{previous_text}`: exit code "
                                f"{previous_code}, the page shows {want}")
            continue
        if args.only and args.only not in c.text:
            previous_code = None
            continue
        missing, links = needed_files(c.text, shared)
        if missing:
            skipped.append(f"{where}: `{c.text}` (missing {', '.join(missing)})")
            previous_code = None
            continue
        with tempfile.TemporaryDirectory(prefix="skin-readme-") as tmp:
            cwd = os.path.join(tmp, "work")
            os.mkdir(cwd)
            for name, src in links.items():
                os.symlink(src, os.path.join(cwd, name))
            # examples/*.json name the shared data as ../../shared/data from their own folder.
            shutil.copytree(os.path.join(source, "examples"), os.path.join(cwd, "examples"))
            os.makedirs(os.path.join(tmp, "shared"))
            if os.path.isdir(shared):
                os.symlink(shared, os.path.join(tmp, "shared", "data"))
            code, actual, seconds, cpu = run(c.text, cwd, skin_dir, args.timeout)
        ran += 1
        total_cpu += cpu
        print(f"{seconds:6.1f} s ({cpu:5.1f} s CPU)  {where}: {c.text.splitlines()[0]}", flush=True)
        nxt = commands.index(c) + 1
        expects_error = nxt < len(commands) and commands[nxt].text.strip() == "echo $?"
        previous_code, previous_text = code, c.text
        problem = None
        if code != 0 and not expects_error:
            problem = f"exit code {code} (the page shows no `echo $?` after it)"
        elif c.expected and c.expected[0][1].lstrip().startswith("{"):
            try:
                want = parse_json_pattern("\n".join(t for _, t in c.expected))
            except ValueError as e:
                problem = f"the page's JSON at line {c.expected[0][0]} does not parse: {e}"
            else:
                try:
                    got = json.loads("\n".join(actual))
                except ValueError as e:
                    problem = f"output is not one JSON object ({e})"
                else:
                    diff = json_subset(want, got)
                    if diff:
                        problem = f"JSON differs at {diff}"
        else:
            m = match_lines(c.expected, actual)
            if m is not None:
                line_no, want, j = m
                got = actual[j] if j is not None else "(end of output)"
                at = f"{shown_page}:{line_no}" if line_no else "after the page's last line"
                problem = (f"output line {j + 1 if j is not None else len(actual) + 1} differs "
                           f"({at}):\n    page:   {want}\n    output: {got}")
        if problem:
            shown = "\n".join("    | " + l for l in actual[:60])
            more = f"\n    | ... ({len(actual) - 60} more lines)" if len(actual) > 60 else ""
            failures.append(f"{where}: `{c.text}`\n  {problem}\n  whole output:\n{shown}{more}")
    return failures, skipped, ran, total_cpu


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    source = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skin", help="the skin executable (not needed with --links-only)")
    ap.add_argument("--page", "--readme", action="append", dest="pages", metavar="FILE",
                    help="a Markdown page to check (repeatable); default: "
                         + ", ".join(DEFAULT_PAGES))
    ap.add_argument("--links-only", action="store_true",
                    help="check the links, scripts and two commands only; run nothing")
    ap.add_argument("--shared-data", default=os.path.join(source, "..", "shared", "data"))
    ap.add_argument("--only", default="", help="run only commands containing this text")
    ap.add_argument("--timeout", type=float, default=120, help="seconds per command")
    args = ap.parse_args()
    if not args.links_only and not args.skin:
        ap.error("--skin is required unless --links-only is given")
    pages = args.pages or [os.path.join(source, p) for p in DEFAULT_PAGES]

    link_problems = []
    for page in pages:
        link_problems += check_links(page, os.path.relpath(page), source)
    print(f"links: {len(pages)} pages, {len(link_problems)} problems", flush=True)
    for p in link_problems:
        print(f"BROKEN {p}")
    if args.links_only:
        return 1 if link_problems else 0

    skin_dir = os.path.dirname(os.path.abspath(args.skin))
    shared = os.path.abspath(args.shared_data)
    failures, skipped, ran, total_cpu = [], [], 0, 0.0
    total_start = time.monotonic()
    for page in pages:
        r = check_commands(page, os.path.relpath(page), source, skin_dir, shared, args)
        failures += r[0]
        skipped += r[1]
        ran += r[2]
        total_cpu += r[3]

    print(f"\n{ran} commands run in {time.monotonic() - total_start:.1f} s ({total_cpu:.1f} s CPU), "
          f"{len(failures)} differ, {len(skipped)} skipped; {len(link_problems)} link problems")
    for s in skipped:
        print(f"SKIPPED {s}")
    for f in failures:
        print(f"\nDIFFERS {f}")
    return 1 if failures or link_problems else 0


if __name__ == "__main__":
    sys.exit(main())
