"""The group 'heavy': the run tests of 100 s and more (ctest label `bench`), which
`scripts/test` leaves out. Runs them through ctest in the build folder, with their own checks,
and reports each one's result and wall time."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

TITLE = "Heavy runs (ctest label bench)"


def run_heavy(build: Path) -> list[tuple[str, str, float]]:
    """(test, Passed/Failed/..., seconds) of every ctest entry labelled bench."""
    done = subprocess.run(["ctest", "-L", "bench", "-j", "2", "--output-on-failure",
                           "--timeout", "1800"], cwd=build, capture_output=True, text=True)
    rows = []
    for line in done.stdout.splitlines():
        m = re.search(r"Test +#\d+: (\S+) \.*\**\s*(\w[\w ]*?)\s+([\d.]+) sec", line)
        if m:
            rows.append((m.group(1), m.group(2).strip(), float(m.group(3))))
    if done.returncode != 0:
        print(done.stdout[-4000:])
    return rows


def sections(args, workdir: Path) -> dict[str, str]:
    """The table of the heavy runs (each checked by its own script of tests/runs/checks)."""
    rows = run_heavy(Path(args.build))
    lines = [f"## {TITLE}",
             "Written by `scripts/bench --only heavy`: the run tests that take 100 s or more "
             "of the 2 cores (`tests/runs/CMakeLists.txt`, label `bench`: what each checks is "
             "written beside it there). `scripts/test` leaves them out; what they cross is "
             "tested there in parts (the tetrahedral BiV mechanics, the BiV closed loop on "
             "hexahedra, the tetrahedral calibration and unloading, the unloaded-reference "
             "calibration on hexahedra). Wall times of this machine, for orientation only.", "",
             "| ctest entry | result | wall time [s] |", "|---|---|---|"]
    lines += [f"| `{name}` | {result} | {seconds:.0f} |" for name, result, seconds in rows]
    if not rows:
        lines.append("| (no entry ran: is the build configured?) | | |")
    section = "\n".join(lines) + "\n"
    print(section)
    return {TITLE: section}
