#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Fails when an #include points up a layer or across rooms the wrong way (the layering of README.md), or
when a library source file exceeds MAX_LINES (the style guide's limit), or when a library header is included
without its "dualgraph/" prefix (the installed layout: #include "dualgraph/core/graph.h").

Layers, lowest first: core < types < solvers < dual_graph < frontend < tools (bench, python, examples and
test sit above all of them). Inside frontend, rooms lowest first: the onboard ones gates < io < calibration < pipeline,
then the offline ones simulation < replay (the sequence replay, calibrations by runs) < evaluation < report; frontend/
itself holds no source.
A file may include its own layer or room and anything below, so onboard code never includes offline code. The
onboard rooms' sources make the library dualgraph_onboard (ONBOARD_SOURCES in frontend/CMakeLists.txt), the
offline ones dualgraph_frontend (FRONTEND_SOURCES): checked too.
Usage: check_layers.py REPOSITORY_ROOT; prints one line per violation and exits 1 if there is any.
"""
import pathlib
import re
import sys

LAYERS = ["core", "types", "solvers", "dual_graph", "frontend", "tools"]
FRONTEND_ROOMS = ["gates", "io", "calibration", "pipeline", "simulation", "replay", "evaluation", "report"]
ONBOARD_ROOMS = FRONTEND_ROOMS[:FRONTEND_ROOMS.index("pipeline") + 1]
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
        sub = parts[1] if len(parts) > 2 else ""  # a source flat in frontend/ ranks above every room: flagged below
        room = FRONTEND_ROOMS.index(sub) if sub in FRONTEND_ROOMS else len(FRONTEND_ROOMS)
    return layer, room


def listed_sources(cmake_text: str, variable: str):
    """The sources of set(VARIABLE ...) in a CMakeLists text, one a line."""
    match = re.search(r"set\(" + variable + r"\n(.*?)\n\)", cmake_text, re.S)
    if not match:
        return None
    return [line.split("#")[0].strip() for line in match.group(1).splitlines() if line.split("#")[0].strip()]


def check_library_split(root: pathlib.Path):
    """Every onboard-room source in ONBOARD_SOURCES, every other frontend source in FRONTEND_SOURCES."""
    cmake = (root / "frontend" / "CMakeLists.txt").read_text(encoding="utf-8")
    onboard, offline = listed_sources(cmake, "ONBOARD_SOURCES"), listed_sources(cmake, "FRONTEND_SOURCES")
    if onboard is None or offline is None:
        return ["frontend/CMakeLists.txt: set(ONBOARD_SOURCES ...) and set(FRONTEND_SOURCES ...) not found"]
    problems = []
    for source in sorted((root / "frontend").rglob("*.cpp")):
        path = source.relative_to(root / "frontend").as_posix()
        room = path.split("/")[0] if "/" in path else ""
        expected, other = (onboard, "ONBOARD_SOURCES") if room in ONBOARD_ROOMS else (offline, "FRONTEND_SOURCES")
        if path not in expected:
            problems.append(f"frontend/{path}: not in {other} of frontend/CMakeLists.txt (room '{room or 'frontend'}')")
    return problems


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
    violations += check_library_split(root)
    flat = [p.name for p in (root / "frontend").iterdir() if p.is_file()]
    if len(flat) > 4:  # issue 52: frontend/ holds its rooms, not code
        violations.append(f"frontend/: {len(flat)} flat files ({', '.join(sorted(flat))}), at most 4: put code in a room")
    for line in violations:
        print(line)
    if not violations:
        print(f"layering: no include points up ({', '.join(LAYERS)}; frontend rooms, onboard gates < io < calibration "
              f"< pipeline, then offline simulation < replay < evaluation < report), the onboard rooms' sources "
              f"in dualgraph_onboard and the rest in dualgraph_frontend; no library file over {MAX_LINES} lines")
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
