#!/usr/bin/env python3
"""Write failures lose nothing: a heartbeat whose results file or checkpoint cannot be
written stops with one clear line, keeps what it wrote before, and resumes to the same
results as an uninterrupted run.

    write_failure.py SYSTOLE PRM [REFERENCE.h5]
    write_failure.py --intact RUN_FOLDER

The second form checks that every checkpoint in RUN_FOLDER matches its MANIFEST (and that
there is one), e.g. the checkpoint a run that failed for good wrote.

PRM is a small heartbeat; every mode runs in the current folder with its own run name
(an Output subsection appended to a copy of PRM) and a checkpoint every 10 steps.

- reference: the uninterrupted run, or REFERENCE.h5 if given (an uninterrupted run of PRM
  made elsewhere, e.g. its own run test: the checkpoints and fields do not change the rows).
- results: the file size is limited (RLIMIT_FSIZE, SIGXFSZ ignored, so a write beyond it
  fails with EFBIG as on a full disk) to the size the results file has after step 30 (a
  run killed there by Output / Test kill after step measures it), so a later row cannot
  be written. Exit 1 (no signal), one 'systole: error:' line naming results.h5 and the
  reason, no stack trace; the file reads with h5py and its rows are the reference's
  first rows (at least 30, fewer than all); the newest checkpoint matches its MANIFEST;
  resumed without the limit, the run ends with the reference's rows.
- checkpoint: Output / Test file size limit in checkpoint = 20 makes the writes of the
  checkpoint of step 20 fail. One line naming the checkpoint, state.txt and the intact
  checkpoint_000010, which matches its MANIFEST; the results rows up to step 20 equal
  the reference's; resumed, the run ends with the reference's rows.

- results_2, checkpoint_2: both faults on 2 ranks, made by the test hooks Output / Test
  file size limit after step = 30 (the results file cannot grow after that step) and in
  checkpoint = 20: the one line, no hang, the rows and the last checkpoint readable.

Rows are compared to 1e-12 (relative to each column's largest value; the wall-time
columns *_seconds excepted).
"""

import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import zlib
from pathlib import Path

import h5py
import numpy as np

GROUPS = ("timeseries", "events", "summary")


def prm_for(prm: Path, run: str, output: str = "") -> Path:
    out = Path(f"{run}.prm")
    out.write_text(prm.read_text() + "\nsubsection Output\n  set Run name = " + run +
                   "\n  set Checkpoint interval = 10\n  set Field output interval = 10\n" +
                   output + "end\n")
    return out


def run(systole: str, prm: Path, limit: int = 0, ranks: int = 1) -> subprocess.CompletedProcess:
    def limited() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    # PMIx keeps its data in shared-memory files larger than the limit: use its hash
    # store instead (MPI_Init fails otherwise).
    env = dict(os.environ, PMIX_MCA_gds="hash")
    command = [systole, str(prm)]
    if ranks > 1:
        command = [shutil.which("mpirun"), "--allow-run-as-root", "--oversubscribe", "-np",
                   str(ranks)] + command
    return subprocess.run(command, capture_output=True, text=True, env=env,
                          preexec_fn=limited if limit else None, timeout=250)


def one_error_line(result: subprocess.CompletedProcess, *words: str) -> str:
    assert result.returncode == 1, f"exit {result.returncode}; stderr:\n{result.stderr}"
    lines = re.findall(r"^systole: error: .*$", result.stderr, re.MULTILINE)
    assert len(lines) == 1, f"{len(lines)} error lines:\n{result.stderr}"
    assert not re.search("Stacktrace|An error occurred in line", result.stderr)
    for word in words:
        assert re.search(word, lines[0]), f"'{word}' not in: {lines[0]}"
    print(lines[0])
    return lines[0]


def rows(path: Path) -> dict:
    with h5py.File(path, "r") as f:
        return {g: {k: f[g][k][()] for k in f[g]} for g in GROUPS if g in f}


def compare_prefix(got: dict, reference: dict, complete: bool) -> int:
    """Every table of got equals the first rows of reference's; returns the time-series
    rows. complete: as many rows as the reference."""
    for group, columns in reference.items():
        if group not in got:
            assert not complete and group != "timeseries", f"/{group} missing"
            continue
        for name, ref in columns.items():
            value = got[group][name]
            n = len(value)
            assert n <= len(ref) and (not complete or n == len(ref)), (group, name, n)
            if name.endswith("_seconds"):
                continue
            # NaN (a quantity without value, e.g. the first beat's change) in the
            # same rows.
            assert np.array_equal(np.isnan(value), np.isnan(ref[:n])), (group, name)
            finite = ~np.isnan(value)
            scale = max(1.0, float(np.nanmax(np.abs(ref)))) if finite.any() else 1.0
            error = float(np.max(np.abs(value - ref[:n])[finite], initial=0)) / scale
            assert error <= 1e-12, f"/{group}/{name}: {error:.3g}"
    return len(got["timeseries"]["time"])


def intact(checkpoint: Path) -> None:
    """Every file of the checkpoint matches its MANIFEST (size, CRC-32)."""
    lines = (checkpoint / "MANIFEST").read_text().split("\n")
    n = 0
    for line in filter(None, lines):
        size, crc, name = line.split()
        data = (checkpoint / name).read_bytes()
        assert len(data) == int(size) and zlib.crc32(data) == int(crc, 16), name
        n += 1
    assert n > 0
    print(f"{checkpoint}: {n} files match the manifest")


def resume(systole: str, prm: Path, name: str, reference: dict) -> None:
    resumed = prm_for(prm, name, "  set Resume = true\n")
    result = run(systole, resumed)
    assert result.returncode == 0, result.stderr
    n = compare_prefix(rows(Path(f"results/{name}/results.h5")), reference, complete=True)
    print(f"{name}: resumed to the end, {n} rows equal to the reference")


def main() -> int:
    if sys.argv[1] == "--intact":
        checkpoints = sorted(Path(sys.argv[2]).glob("checkpoint_*"))
        assert checkpoints, f"no checkpoint in {sys.argv[2]}"
        for checkpoint in checkpoints:
            intact(checkpoint)
        return 0
    systole, prm = sys.argv[1], Path(sys.argv[2]).resolve()
    shutil.rmtree("results", ignore_errors=True)
    if len(sys.argv) > 3:
        reference = rows(Path(sys.argv[3]))
    else:
        assert run(systole, prm_for(prm, "reference")).returncode == 0
        reference = rows(Path("results/reference/results.h5"))
    n_reference = len(reference["timeseries"]["time"])

    # The results file cannot grow after step 30.
    probe = run(systole, prm_for(prm, "probe", "  set Test kill after step = 30\n"))
    assert probe.returncode == -signal.SIGKILL, probe.returncode
    limit = Path("results/probe/results.h5").stat().st_size
    result = run(systole, prm_for(prm, "results"), limit)
    one_error_line(result, r"results/results/results\.h5", "File too large",
                   "rows written before are kept")
    n = compare_prefix(rows(Path("results/results/results.h5")), reference, complete=False)
    assert 30 <= n < n_reference, n
    print(f"results: {n} of {n_reference} rows kept, equal to the reference")
    checkpoints = sorted(Path("results/results").glob("checkpoint_*"))
    intact(checkpoints[-1])
    resume(systole, prm, "results", reference)

    # The checkpoint of step 20 cannot be written.
    result = run(systole, prm_for(prm, "checkpoint",
                                  "  set Test file size limit in checkpoint = 20\n"))
    one_error_line(result, "checkpoint of step 20", r"state\.txt: File too large",
                   r"checkpoint_000010, is intact")
    intact(Path("results/checkpoint/checkpoint_000010"))
    n = compare_prefix(rows(Path("results/checkpoint/results.h5")), reference,
                       complete=False)
    print(f"checkpoint: {n} rows kept, equal to the reference")
    resume(systole, prm, "checkpoint", reference)

    # The same on 2 ranks, through the test hooks (mpirun's daemons reset SIGXFSZ, so an
    # outside limit kills the ranks): every rank stops with the one line, none hangs.
    result = run(systole, prm_for(prm, "results_2",
                                  "  set Test file size limit after step = 30\n"), ranks=2)
    one_error_line(result, r"results/results_2/results\.h5", "File too large")
    with h5py.File("results/results_2/results.h5", "r") as f:
        n = len(f["timeseries"]["time"])
    assert 31 <= n < n_reference, n
    intact(sorted(Path("results/results_2").glob("checkpoint_*"))[-1])
    print(f"results_2: {n} rows kept")
    result = run(systole, prm_for(prm, "checkpoint_2",
                                  "  set Test file size limit in checkpoint = 20\n"), ranks=2)
    one_error_line(result, "checkpoint of step 20", r"checkpoint_000010, is intact")
    intact(Path("results/checkpoint_2/checkpoint_000010"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
