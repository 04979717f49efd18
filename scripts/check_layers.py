#!/usr/bin/env python3
"""Check the layering of src/: a folder may include only itself and lower layers, and inside a
folder the units (a .h with its .cc) include each other without a circle.

Order (STYLE.md 2.3): base <- geometry <- fibres <- materials <- {electrophysiology,
mechanics} <- circulation <- postprocess <- simulation; io sits beside simulation and may use any
layer below simulation; inverse (calibration) sits beside circulation. Exit status 1 lists every offending include.
"""

import re
import sys
from pathlib import Path

ORDER = {
    "base": 0,
    "geometry": 1,
    "fibres": 2,
    "materials": 3,
    "electrophysiology": 4,
    "mechanics": 4,
    "circulation": 5,
    "io": 5,
    "inverse": 5,
    "postprocess": 6,
    "simulation": 7,
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/')


def violations(src: Path):
    """Yield (file, line number, text) of every include of a higher or sibling layer."""
    for path in sorted(src.rglob("*")):
        if path.suffix not in (".h", ".cc"):
            continue
        folder = path.relative_to(src).parts[0]
        if folder not in ORDER:
            yield path, 0, f"folder '{folder}' is not in the layer list of {__file__}"
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            match = INCLUDE.match(line)
            if not match:
                continue
            target = match.group(1)
            if target == folder:
                continue
            if target not in ORDER:
                yield path, number, f"includes unknown folder '{target}'"
            elif ORDER[target] >= ORDER[folder]:
                yield path, number, f"{folder} may not include {target}: {line.strip()}"


FILE_INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/([a-z_0-9]+)\.h"')


def unit_circles(src: Path):
    """Yield (file, 0, text) for every circle of includes between units of one folder (a unit:
    x.h with x.cc and x_impl.h; x.cc including y.h and y.cc including x.h is a circle)."""
    edges: dict[str, set[str]] = {}
    for path in sorted(src.rglob("*")):
        if path.suffix not in (".h", ".cc"):
            continue
        # (x_impl.h, the private part of a pimpl class x, belongs to unit x.)
        unit = f"{path.relative_to(src).parts[0]}/{path.stem.removesuffix('_impl')}"
        edges.setdefault(unit, set())
        for line in path.read_text().splitlines():
            match = FILE_INCLUDE.match(line)
            if match and match.group(1) == unit.split("/")[0]:
                target = f"{match.group(1)}/{match.group(2).removesuffix('_impl')}"
                if target != unit:
                    edges[unit].add(target)
    # Tarjan's strongly connected components.
    index, low, stack, on_stack, counter = {}, {}, [], set(), [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                yield_list.append(sorted(component))

    yield_list: list[list[str]] = []
    sys.setrecursionlimit(10000)
    for v in sorted(edges):
        if v not in index:
            visit(v)
    for component in yield_list:
        yield src / (component[0] + ".h"), 0, "units include each other in a circle: " + \
            " <-> ".join(component)


def main() -> int:
    src = Path(__file__).resolve().parent.parent / "src"
    bad = list(violations(src)) + list(unit_circles(src))
    for path, number, text in bad:
        print(f"{path.relative_to(src.parent)}:{number}: {text}", file=sys.stderr)
    if not bad:
        print("layering ok")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
