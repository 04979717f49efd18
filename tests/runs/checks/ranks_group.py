#!/usr/bin/env python3
"""One short run of a problem family on a given rank count (the ctest label `ranks`).

    ranks_group.py SYSTOLE MPIEXEC PRM NAME RANKS [--tolerance TOL] [--floor ABS]
                   [--set "Section / Entry = value" ...]

Runs PRM with the --set entries appended (and Output / Run name = NAME_RANKS) on RANKS ranks
in the current folder. With RANKS > 1 the results must equal those of NAME_1 (the same run on
1 rank, made first) to TOL relative plus ABS (checks/compare_ranks.py, --fields: /timeseries,
/events, /summary and the last field step).
"""

import argparse
import re
import subprocess
import sys
from pathlib import Path

import compare_ranks


def appended(entry: str) -> str:
    path, sep, value = entry.partition("=")
    sections = [s.strip() for s in path.split("/")]
    if not sep or len(sections) < 1 or not sections[-1]:
        sys.exit(f"--set '{entry}': expected 'Section / Entry = value'")
    text = "".join(f"subsection {s}\n" for s in sections[:-1])
    text += f"  set {sections[-1]} = {value.strip()}\n" + "end\n" * (len(sections) - 1)
    return text


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("systole")
    parser.add_argument("mpiexec")
    parser.add_argument("prm", type=Path)
    parser.add_argument("name")
    parser.add_argument("ranks", type=int)
    parser.add_argument("--tolerance", default="1e-8")
    parser.add_argument("--floor", default="1e-10")
    parser.add_argument("--set", action="append", default=[])
    args = parser.parse_args()

    run = f"{args.name}_{args.ranks}"
    # A mesh file named relative to PRM's folder, named from here.
    text = re.sub(r"(set Mesh file\s*=\s*)(\S+)",
                  lambda m: m.group(1) + str((args.prm.parent / m.group(2)).resolve()),
                  args.prm.read_text())
    text += "\n" + "".join(appended(e) for e in args.set)
    text += f"subsection Output\n  set Run name = {run}\n  set Progress = off\nend\n"
    prm = Path(f"{run}.prm")
    prm.write_text(text)
    command = [args.mpiexec, "--allow-run-as-root", "--oversubscribe", "-np",
               str(args.ranks), args.systole, str(prm)]
    p = subprocess.run(command, capture_output=True, text=True)
    Path(f"{run}.log").write_text(p.stdout + p.stderr)
    if p.returncode != 0:
        print((p.stdout + p.stderr)[-3000:])
        print(f"FAIL: {' '.join(command)} exited with {p.returncode}")
        return 1
    if args.ranks == 1:
        print(f"results/{run}/results.h5 written")
        return 0
    sys.argv = ["compare_ranks.py", f"results/{args.name}_1/results.h5",
                f"results/{run}/results.h5", "--tolerance", args.tolerance,
                "--floor", args.floor, "--fields"]
    return compare_ranks.main()


if __name__ == "__main__":
    sys.exit(main())
