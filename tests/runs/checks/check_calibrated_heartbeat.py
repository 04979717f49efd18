#!/usr/bin/env python3
"""Check a heartbeat that started from a calibration's calibrated.prm.

    check_calibrated_heartbeat.py HEARTBEAT.h5 CALIBRATION.h5 MESH.msh [check_heartbeat options]

The heartbeat passes check_heartbeat.py, and the values it used (the entries printed in its
results file's /parameters, "All entries with the values used") are the calibration's: every
fitted entry of /calibration/parameters (to 1e-9 relative), Geometry / Type = gmsh and the
Mesh file MESH (the calibration's unloaded mesh). The heartbeat's first filling starts from
the unloaded cavity: its mesh's cavity volume (computed here from MESH, closed by the base
plane) is the calibration's reported unloaded volume (to 1e-6 relative).
"""

import re
import sys
from pathlib import Path

import h5py

from check_heartbeat import main as check_heartbeat
from systole_post.gmsh_mesh import cavity_volume, read_msh
from systole_post.results import read_results


def used_entries(text: str) -> dict:
    """'Section / Sub / entry' -> value from the ShortPRM part of /parameters."""
    used = text.split("# All entries with the values used:", 1)[1]
    path, entries = [], {}
    for line in used.splitlines():
        line = line.split("#", 1)[0].strip()
        if line.startswith("subsection "):
            path.append(line[len("subsection "):].strip())
        elif line == "end":
            path.pop()
        elif line.startswith("set "):
            name, value = line[4:].split("=", 1)
            entries[" / ".join(path + [name.strip()])] = value.strip()
    return entries


def main(argv) -> int:
    heartbeat, calibration, mesh = argv[1:4]
    failures = []
    if check_heartbeat([argv[0], heartbeat] + argv[4:]) != 0:
        failures.append("the heartbeat checks failed")
    entries = used_entries(read_results(heartbeat).parameters)
    with h5py.File(calibration, "r") as f:
        par = f["calibration/parameters"]
        names = [n.decode() if isinstance(n, bytes) else str(n) for n in par["name"][()]]
        fitted = dict(zip(names, par["fitted"][()]))
        unloaded_mL = f["statistics/unloaded_volume_mL"][()]
    law = entries["Material / Passive law"]
    for name, value in fitted.items():
        used = float(entries[f"Material / {law} / {name}"])
        print(f"{name}: fitted {value:.10g}, used by the heartbeat {used:.10g}")
        if abs(used / value - 1) > 1e-9:
            failures.append(f"{name}: the heartbeat used {used}, the fit gave {value}")
    if entries["Geometry / Type"] != "gmsh":
        failures.append(f"Geometry / Type is {entries['Geometry / Type']}, not gmsh")
    if Path(entries["Geometry / Gmsh / Mesh file"]).resolve() != Path(mesh).resolve():
        failures.append(f"the heartbeat's mesh {entries['Geometry / Gmsh / Mesh file']} "
                        f"is not {mesh}")
    m = read_msh(mesh)
    lid = m.nodes[m.quads[m.names["base"]]][..., 2].max()
    volume = cavity_volume(m, "endocardium", lid) / 1000
    print(f"unloaded mesh cavity {volume:.6f} mL, calibration reported {unloaded_mL:.6f} mL")
    if abs(volume / unloaded_mL - 1) > 1e-6:
        failures.append("the unloaded mesh's cavity is not the reported unloaded volume")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
