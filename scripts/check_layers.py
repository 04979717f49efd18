#!/usr/bin/env python3
"""Check the layering of src/: a folder may include only itself and lower layers.

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


def main() -> int:
    src = Path(__file__).resolve().parent.parent / "src"
    bad = list(violations(src))
    for path, number, text in bad:
        print(f"{path.relative_to(src.parent)}:{number}: {text}", file=sys.stderr)
    if not bad:
        print("layering ok")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
