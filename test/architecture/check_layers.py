#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Fails when an #include points up a layer or across rooms the wrong way (the layering of README.md), or
when a library source file exceeds MAX_LINES (the style guide's limit), or when a library header is included
without its "dualgraph/" prefix (the installed layout: #include "dualgraph/core/graph.h").

Layers, lowest first: core < types < solvers < dual_graph < frontend < tools (bench, python, examples and
test sit above all of them). Inside frontend, rooms lowest first: gates < io < simulation < calibration < pipeline < (root:
sequence_run, the replays and calibrations by runs) < evaluation < report. A file may include its own layer or room and anything below.
Usage: check_layers.py REPOSITORY_ROOT; prints one line per violation and exits 1 if there is any.
"""
import pathlib
import re
import sys

LAYERS = ["core", "types", "solvers", "dual_graph", "frontend", "tools"]
FRONTEND_ROOMS = ["gates", "io", "simulation", "calibration", "pipeline", "", "evaluation", "report"]  # "" = frontend/ itself
MAX_LINES = 400
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def rank(path: str):
    """(layer index, room index) of a repository path, or None for files outside the library layers."""
    parts = path.split("/")
    if parts[0] not in LAYERS:
        return None
    layer = LAYERS.index(parts[0])
    room = 0
    if parts[0] == "frontend":
        sub = parts[1] if len(parts) > 2 else ""
        room = FRONTEND_ROOMS.index(sub) if sub in FRONTEND_ROOMS else len(FRONTEND_ROOMS)
    return layer, room


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    violations = []
    for layer in LAYERS:
        for source in sorted((root / layer).rglob("*")):
            if source.suffix not in (".h", ".cpp"):
                continue
            path = source.relative_to(root).as_posix()
            own = rank(path)
            text = source.read_text(encoding="utf-8", errors="replace")
            lines = text.count("\n")
            if layer != "tools" and lines > MAX_LINES:
                violations.append(f"{path}: {lines} lines, over the {MAX_LINES}-line limit")
            for included in INCLUDE.findall(text):
                if rank(included) is not None and rank(included)[0] < LAYERS.index("tools"):
                    violations.append(f"{path}: includes \"{included}\": library headers are included as "
                                      f"\"dualgraph/{included}\" (as once installed)")
                    continue
                target = rank(included[len("dualgraph/"):]) if included.startswith("dualgraph/") else None
                if target is not None and target > own:
                    violations.append(f"{path}: includes {included}, which is above it")
    for line in violations:
        print(line)
    if not violations:
        print(f"layering: no include points up ({', '.join(LAYERS)}; frontend rooms gates < io < simulation < "
              f"calibration < pipeline < sequence_run < evaluation < report); no library file over {MAX_LINES} lines")
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
