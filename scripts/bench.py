#!/usr/bin/env python3
"""Benchmarks of Systole: refinement studies of the Land et al. 2015 problems.

Runs each case through the systole app (1 or 2 MPI ranks), reads its results file (the
time series, the summary and /statistics: wall time, peak memory, sizes, timer sections,
Newton, Krylov and ARKode counts; no log lines), and writes docs/verification.md. The fibre
generators' costs come from systole-fibres (the rule-based solves it logs; it writes no
results file) and from the hidden unit test [dti-bench] (DTI mapping time per million
points).
Timings are what this machine measured; they are reported, never asserted.

The groups are the modules of scripts/systole_bench/ (the table: systole_bench.groups);
this script parses the arguments and walks the table.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from systole_bench.core import ROOT, write_docs
from systole_bench.groups import GROUPS


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """The command line (scripts/bench passes --build)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", type=Path, default=ROOT / "build")
    parser.add_argument("--quick", action="store_true", help="skip the finest levels")
    parser.add_argument("--full", action="store_true",
                        help="land: sweep parameters/lv_heartbeat_ttp_land.prm (hours) in place "
                        "of the coarse ventricle; niederer: also h = 0.1 mm with dt = 0.01 and "
                        "0.005 ms (many hours)")
    parser.add_argument("--jobs", type=int, default=1,
                        help="land: runs at a time (1: 2 ranks each; more: 1 rank each)")
    parser.add_argument("--output", type=Path, default=ROOT / "docs" / "verification.md")
    parser.add_argument("--only", choices=list(GROUPS),
                        help="run one group and replace its sections of the output (the other "
                        "sections are kept)")
    parser.add_argument("--no-write", action="store_true",
                        help="print the tables only; do not touch the output")
    return parser.parse_args(argv)


def main() -> int:
    """Run every group (or the one of --only) in the order of the table; write the output."""
    args = parse_args()
    sections = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, group in GROUPS.items():
            if args.only in (None, name):
                sections.update(group(args, Path(tmp)))
    if args.no_write:
        return 0
    write_docs(args.output, sections, replace_only=args.only is not None)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
