"""The 0D closed loop of `systole` (Problem = circulation) against an independent implementation.

The reference (systole_post/closed_loop_reference.py) is written from
reference/physiology.md ("Closed-loop circulation", Regazzoni et al. 2022) in that file's
units (mL, mmHg, s), not from the C++ code, and is integrated with SciPy's Radau at tight
tolerances. The app runs 5 beats with its defaults
(which must be the physiology.md values) at tight tolerances; every state must agree to
1e-6 relative (the largest difference over the run divided by the state's largest
magnitude) at the output times, which must be exact multiples of the output interval, and
the blood volume must stay constant to 1e-8 relative.

The app is `$SYSTOLE_APP`, else `$SYSTOLE_BUILD/systole`, else `build/systole` of the
repository. Without it the tests are skipped, unless `SYSTOLE_REQUIRE_APP` is set (the
ctest entry run.circulation_closed_loop_reference sets both).
"""

import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from conftest import SCRIPTS_DIR
from systole_post.closed_loop_reference import (STATES, blood_volume, chamber_pressure,
                                                 reference_solution)

N_BEATS = 5
OUTPUT_INTERVAL_MS = 1.0


def app_path():
    if "SYSTOLE_APP" in os.environ:
        return Path(os.environ["SYSTOLE_APP"])
    build = os.environ.get("SYSTOLE_BUILD", str(SCRIPTS_DIR.parent / "build"))
    return Path(build) / "systole"


PARAMETERS = f"""# Written by scripts/tests/test_closed_loop_reference.py: the default closed loop.
set Problem = circulation
subsection Time
  set Time step = {OUTPUT_INTERVAL_MS}
end
subsection Circulation
  set Model                     = closed loop
  set Number of beats           = {N_BEATS}
  set Periodicity tolerance     = 0
  set Relative tolerance        = 1e-10
  set Absolute volume tolerance = 1e-9
end
subsection Output
  set Run name = closed_loop
end
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """Run the app once; returns (timeseries, summary) of its results file."""
    app = app_path()
    if not app.is_file():
        if os.environ.get("SYSTOLE_REQUIRE_APP"):
            pytest.fail(f"the systole app {app} does not exist")
        pytest.skip(f"the systole app {app} is not built")
    folder = tmp_path_factory.mktemp("closed_loop")
    (folder / "closed_loop.prm").write_text(PARAMETERS)
    subprocess.run([str(app), "closed_loop.prm"], cwd=folder, check=True, timeout=600,
                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    with h5py.File(folder / "results" / "closed_loop" / "results.h5", "r") as f:
        timeseries = {k: f["timeseries"][k][()] for k in f["timeseries"]}
        summary = {k: f["summary"][k][()] for k in f["summary"]}
    return timeseries, summary


@pytest.fixture(scope="module")
def reference(run):
    timeseries, _ = run
    return reference_solution(timeseries["time"] / 1000.0)


def test_output_times_are_exact_multiples_of_the_interval(run):
    timeseries, _ = run
    expected = np.arange(N_BEATS * 800 / OUTPUT_INTERVAL_MS + 1) * OUTPUT_INTERVAL_MS
    assert np.array_equal(timeseries["time"], expected)


def test_every_state_matches_the_independent_reference(run, reference):
    timeseries, _ = run
    errors = {}
    for i, (name, _) in enumerate(STATES):
        scale = np.max(np.abs(reference[i]))
        errors[name] = np.max(np.abs(timeseries[name] - reference[i])) / scale
    print("largest relative difference per state:",
          {name: f"{e:.2e}" for name, e in errors.items()})
    assert max(errors.values()) < 1e-6, errors


def test_chamber_pressures_match_the_elastance_law(run, reference):
    timeseries, _ = run
    times_s = timeseries["time"] / 1000.0
    for i, name in enumerate(("la", "lv", "ra", "rv")):
        expected = np.array([chamber_pressure(name, t, v) for t, v in zip(times_s, reference[i])])
        error = np.max(np.abs(timeseries[f"{name}_pressure_mmHg"] - expected))
        assert error < 1e-6 * np.max(np.abs(expected)), (name, error)


def test_total_blood_volume_is_constant(run):
    timeseries, summary = run
    volume = timeseries["total_blood_volume_mL"]
    y0 = np.array([value for _, value in STATES])
    assert volume[0] == pytest.approx(blood_volume(y0), rel=1e-12)
    drift = np.max(np.abs(volume - volume[0])) / volume[0]
    print(f"total blood volume {volume[0]:.6f} mL, largest relative change {drift:.2e}")
    assert drift < 1e-8
    assert np.all(summary["total_blood_volume_drift"] < 1e-8)


def test_summary_has_one_row_per_beat_per_ventricle(run, reference):
    _, summary = run
    assert list(summary["beat"]) == list(range(N_BEATS))
    for prefix in ("lv", "rv"):
        for column in ("EDV_mL", "ESV_mL", "EF", "peak_pressure_mmHg"):
            assert len(summary[f"{prefix}_{column}"]) == N_BEATS
    # EDV and ESV of the last beat (the volumes at the valve closures) against the
    # reference's largest and smallest volume at the 1 ms outputs: equal up to the
    # volume that the valves pass within 1 ms of their closure and the leaks.
    last = slice(int((N_BEATS - 1) * 800 / OUTPUT_INTERVAL_MS), None)
    for i, prefix in ((1, "lv"), (3, "rv")):
        volume = reference[i][last]
        assert summary[f"{prefix}_EDV_mL"][-1] == pytest.approx(volume.max(), rel=1e-4)
        assert summary[f"{prefix}_ESV_mL"][-1] == pytest.approx(volume.min(), rel=1e-4)


def test_each_ventricle_passes_its_four_phases_in_order(run):
    timeseries, _ = run
    for prefix in ("lv", "rv"):
        phases = timeseries[f"{prefix}_phase"].astype(int)
        changes = phases[np.flatnonzero(np.diff(phases)) + 1]
        sequence = np.concatenate([[phases[0]], changes])
        # filling 0 -> isovolumetric contraction 1 -> ejection 2 -> isovolumetric relaxation 3
        assert np.all((sequence[1:] - sequence[:-1]) % 4 == 1), (prefix, sequence)
        assert len(sequence) >= 4 * N_BEATS
