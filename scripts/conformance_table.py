#!/usr/bin/env python3
"""The table of docs/conformance.md from the Mitsuba suite's report.

    cargo test --release --test mitsuba_suite -- --nocapture > suite.log 2>&1
    python3 scripts/conformance_table.py suite.log

Prints one markdown row per scene (verdict, channel-mean ratios, the worst channel's error,
the block tests passed, render seconds) and the figure line, read from the lines the test
prints (tests/mitsuba_suite.rs: `scene status R G B blocks min-p seconds` and, indented, the
refusal or the reason a scene is off).
"""
import re
import sys


def main(path):
    lines = open(path, encoding="utf-8", errors="replace").read().splitlines()
    row = re.compile(r"^(\S+\.xml)\s+(pass|fail|refused|error)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)%\s+(\S+)\s+(\S+)$")
    rows, counts = [], {"pass": 0, "fail": 0, "refused": 0, "error": 0}
    for i, line in enumerate(lines):
        m = row.match(line)
        if not m:
            continue
        scene, status, r, g, b, blocks, _, secs = m.groups()
        note = lines[i + 1].strip() if i + 1 < len(lines) and lines[i + 1].startswith("    ") else ""
        counts[status] += 1
        if status == "refused":
            message = note.split(": ", 1)[1] if ": " in note else note
            message = message.replace("<", "&lt;").replace(">", "&gt;")
            rows.append(f"| `{scene}` | refused: {message} | | | | |")
            continue
        ratios = [float(r), float(g), float(b)]
        worst = max(abs(x - 1.0) for x in ratios)
        verdict = "pass" if status == "pass" else "off (" + ", ".join(
            k for k, key in (("means", "channel"), ("blocks", "block tests")) if key in note) + ")"
        rows.append(f"| `{scene}` | {verdict} | {r} / {g} / {b} | {100 * worst:.2f}% | {blocks}% | {secs} |")
    print("| scene | verdict | R / G / B ratio | worst | blocks | s |")
    print("|---|---|---|---|---|---|")
    print("\n".join(rows))
    total = sum(counts.values())
    print(f"\n**{counts['pass']} of {total} pass** on the CPU backend; {counts['refused']} are refused; "
          f"{counts['fail'] + counts['error']} render and are off.")


if __name__ == "__main__":
    main(sys.argv[1])
