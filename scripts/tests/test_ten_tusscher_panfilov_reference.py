"""The ten Tusscher-Panfilov 2006 cell of `systole` (Problem = cell) against SciPy.

The reference (systole_post.ten_tusscher_reference) integrates the Python that gotranx
generated from the same .ode files (systole_post.cellmodels), not the C++ model, with SciPy's
BDF at rtol 1e-8. For each variant (endocardial, mid-myocardial, epicardial) the app paces
one cell at 1 Hz for N_BEATS beats from the model file's initial state, with the model
file's stimulus (52 pA/pF for 1 ms at 10 ms of every beat) and the cell time step of
parameters/cell_ttp.prm; the resting potential, peak potential, APD90 and peak calcium of
every beat must agree to 0.5 % (relative to the reference's magnitude).

The app is `$SYSTOLE_APP`, else `$SYSTOLE_BUILD/systole`, else `build/systole` of the
repository. Without it the tests are skipped, unless `SYSTOLE_REQUIRE_APP` is set (the
ctest entry run.cell_ten_tusscher_panfilov_reference sets both).
"""

import os
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from conftest import SCRIPTS_DIR
from systole_post.ten_tusscher_reference import reference_beats

N_BEATS = 3
TOLERANCE = 0.005
MEASURES = ("resting_potential_mV", "peak_potential_mV", "APD90_ms", "peak_calcium_uM")


def app_path():
    if "SYSTOLE_APP" in os.environ:
        return Path(os.environ["SYSTOLE_APP"])
    build = os.environ.get("SYSTOLE_BUILD", str(SCRIPTS_DIR.parent / "build"))
    return Path(build) / "systole"


def cell_time_step():
    """Electrophysiology / Time step of the shipped parameters/cell_ttp.prm."""
    text = (SCRIPTS_DIR.parent / "parameters" / "cell_ttp.prm").read_text()
    section = text[text.index("subsection Electrophysiology"):]
    return float(re.search(r"set Time step\s*=\s*([0-9.eE+-]+)", section).group(1))


def run_app(folder, cell_type):
    app = app_path()
    if not app.is_file():
        if os.environ.get("SYSTOLE_REQUIRE_APP"):
            pytest.fail(f"the systole app {app} does not exist")
        pytest.skip(f"the systole app {app} is not built")
    (folder / "cell.prm").write_text(f"""# Written by scripts/tests/test_ten_tusscher_panfilov_reference.py
set Problem = cell
subsection Time
  set End time  = {1000 * N_BEATS}
  set Time step = 5
end
subsection Electrophysiology
  set Ionic model = ten Tusscher-Panfilov
  set Time step   = {cell_time_step()}
  subsection ten Tusscher-Panfilov
    set Cell type = {cell_type}
  end
end
subsection Output
  set Run name = cell
end
""")
    subprocess.run([str(app), "cell.prm"], cwd=folder, check=True, timeout=600,
                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    with h5py.File(folder / "results" / "cell" / "results.h5", "r") as f:
        timeseries = {k: f["timeseries"][k][()] for k in f["timeseries"]}
        summary = {k: f["summary"][k][()] for k in f["summary"]}
    return timeseries, summary


@pytest.mark.parametrize("cell_type", ["endocardial", "mid-myocardial", "epicardial"])
def test_cell_agrees_with_the_scipy_reference(tmp_path, cell_type):
    timeseries, summary = run_app(tmp_path, cell_type)
    assert np.all(np.isfinite(timeseries["potential_mV"]))
    assert np.all(np.isfinite(timeseries["calcium_uM"]))
    assert list(summary["beat"]) == list(range(N_BEATS))
    reference = reference_beats(cell_type, N_BEATS)
    failures = []
    for beat, expected in enumerate(reference):
        for name in MEASURES:
            got, want = summary[name][beat], expected[name]
            error = abs(got - want) / abs(want)
            print(f"{cell_type} beat {beat} {name}: systole {got:.5f}, "
                  f"scipy {want:.5f}, relative difference {error:.2e}")
            if not error <= TOLERANCE:
                failures.append(f"beat {beat} {name}: {got} vs {want} ({error:.2e})")
    assert not failures, failures
