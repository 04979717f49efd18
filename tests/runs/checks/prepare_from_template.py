#!/usr/bin/env python3
"""Write a parameter file from a template: @MESH@ becomes an absolute mesh path.

    prepare_from_template.py TEMPLATE.prm MESH OUT.prm

Used by run tests whose mesh is written by an earlier test in the build tree.
"""

import sys
from pathlib import Path


def main(argv) -> int:
    template, mesh, out = argv[1:4]
    mesh = Path(mesh).resolve()
    if not mesh.is_file():
        print(f"no mesh {mesh}: run the test that writes it first")
        return 1
    Path(out).write_text(Path(template).read_text().replace("@MESH@", str(mesh)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
