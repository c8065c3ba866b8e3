#!/usr/bin/python3
"""Parses generated files with Python's own parsers, never running them, for test_escape.cpp:
`parse_exports.py FILE...` prints one JSON document (ASCII) {file: result}:
- *.py: {"strings": {NAME: value}} of the module-level assignments of string constants (ast.parse
  and compile; nothing is executed);
- *.xml, *.mtlx: {"attributes": [[tag, attribute, value], ...]} in document order (expat);
- *.lit: {"values": [...]}: one Python string literal per line, each by ast.literal_eval;
- *.attr: {"values": [...]}: one XML attribute value per line, each as <a v="LINE"/> by expat;
- *.csv: {"rows": [[field, ...], ...]} by the csv module.
A file that does not parse gives {"error": message}."""
import ast
import csv
import io
import json
import sys
import xml.etree.ElementTree as ET


def parse(path):
    text = open(path, "rb").read()
    if path.endswith(".py"):
        tree = ast.parse(text, path)
        compile(tree, path, "exec")
        strings = {}
        for node in tree.body:
            if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
                if isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
                    strings[node.targets[0].id] = node.value.value
        return {"strings": strings}
    if path.endswith((".xml", ".mtlx")):
        root = ET.fromstring(text)
        return {"attributes": [[e.tag, k, v] for e in root.iter() for k, v in e.attrib.items()]}
    if path.endswith(".lit"):
        return {"values": [ast.literal_eval(line) for line in text.decode("utf-8").split("\n") if line]}
    if path.endswith(".attr"):
        lines = [line for line in text.decode("utf-8").split("\n") if line]
        return {"values": [ET.fromstring(('<a v="' + line + '"/>').encode("utf-8")).attrib["v"] for line in lines]}
    if path.endswith(".csv"):
        return {"rows": list(csv.reader(io.StringIO(text.decode("utf-8"), newline="")))}
    raise ValueError("unknown kind of file")


results = {}
for path in sys.argv[1:]:
    try:
        results[path] = parse(path)
    except Exception as e:  # noqa: BLE001 - the test reports which file failed and why
        results[path] = {"error": f"{type(e).__name__}: {e}"}
print(json.dumps(results))
