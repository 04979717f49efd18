#!/usr/bin/env python3
"""Kill a run midway (SIGKILL) and check that its results file is readable and complete.

    kill_midway.py SYSTOLE PRM RESULTS.h5

Starts SYSTOLE PRM, waits until the results file holds at least MIN_ROWS time-series rows,
kills the process with SIGKILL, then reads the file with h5py: every column must hold the
completed rows, times strictly increasing, volumes consistent with the prescribed stretch.
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np

from systole_post.results import read_results

MIN_ROWS = 5
TIMEOUT_S = 120


def rows_written(path: Path) -> int:
    """Rows of /timeseries/time, read while the writer is running (0 if not readable yet)."""
    try:
        with h5py.File(path, "r", locking=False) as f:
            return len(f["timeseries/time"])
    except (OSError, KeyError):
        return 0


def main(argv) -> int:
    systole, prm, results = argv[1], argv[2], Path(argv[3])
    if results.exists():
        results.unlink()  # a file of an earlier run must not count
    env = dict(os.environ, HDF5_USE_FILE_LOCKING="FALSE")
    process = subprocess.Popen([systole, prm], env=env, stdout=subprocess.DEVNULL)
    start = time.monotonic()
    try:
        while rows_written(results) < MIN_ROWS:
            if process.poll() is not None:
                print(f"FAIL: the run ended (exit {process.returncode}) before it could be killed")
                return 1
            if time.monotonic() - start > TIMEOUT_S:
                print("FAIL: no rows appeared in time")
                return 1
            time.sleep(0.05)
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait()

    data = read_results(results)
    ts = data.timeseries
    failures = []
    if data.n_rows < MIN_ROWS:
        failures.append(f"only {data.n_rows} rows survived")
    if not np.all(np.diff(ts["time"]) > 0):
        failures.append("time is not strictly increasing")
    if not np.all(np.isfinite(ts["volume"])):
        failures.append("non-finite volumes")
    if np.max(np.abs(ts["volume"] - ts["volume"][0] * ts["stretch"] ** 3)) > 1e-8 * ts["volume"][0]:
        failures.append("volumes inconsistent with the stretch")
    if "Problem" not in data.parameters:
        failures.append("/parameters does not hold the parameter text")
    for failure in failures:
        print("FAIL:", failure)
    print(f"killed after {data.n_rows} complete rows; file readable")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
