"""The group 'badinput': the bad-input sweep (scripts/bad_input_sweep.py), 600 mutated
parameter cases and every mesh case."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from .core import ROOT


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}: the sweep's own markdown."""
    # A sibling script of scripts/bench.py (its folder is on sys.path).
    from bad_input_sweep import SECTION_TITLE

    print("running the bad-input sweep (about 15 minutes) ...", flush=True)
    markdown = workdir / "bad_input.md"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "bad_input_sweep.py"),
                    "--systole", str(args.build / "systole"), "--sample", "600",
                    "--markdown", str(markdown)], check=False)
    text = markdown.read_text()
    print(text, flush=True)
    return {SECTION_TITLE: text}
