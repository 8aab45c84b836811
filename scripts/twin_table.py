#!/usr/bin/env python3
"""Regenerates docs/architecture.md's oracle table from tests/twin_names.rs's TWINS list
(the test checks that every row is there; this keeps the two in step)."""
import re
import sys
from pathlib import Path

root = Path(__file__).resolve().parent.parent
test = (root / "tests/twin_names.rs").read_text()
body = test.split("const TWINS")[1].split("];")[0]
rows = []
for m in re.finditer(r'\("([^"]*)", "([^"]*)", "([^"]*)", "([^"]*)", (Oracle|Caller|Helper)(?:\("([^"]*)"\))?\)', body):
    wf, wn, rf, rn, kind, t = m.groups()
    twin = "device-only helper" if kind == "Helper" else f"`{rf}`: `{rn}`"
    how = {"Oracle": f"oracle, `tests/{t}`", "Caller": f"through its callers, `tests/{t}`",
           "Helper": "through its callers"}[kind]
    rows.append(f"| `{wf}` | `{wn}` | {twin} | {how} |")
doc_path = root / "docs/architecture.md"
lines = doc_path.read_text().split("\n")
first = next(i for i, l in enumerate(lines) if l.startswith("| `") and l.count("|") == 5)
last = first
while last + 1 < len(lines) and lines[last + 1].startswith("| `"):
    last += 1
lines[first:last + 1] = rows
doc_path.write_text("\n".join(lines))
print(f"{len(rows)} rows", file=sys.stderr)
