"""Shared pytest setup: put scripts/ on sys.path and build tiny results files."""

import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

SCRIPTS_DIR = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(SCRIPTS_DIR))

#: Units of the columns the helper knows; other columns get "-".
UNITS = {"time": "ms", "step": "-", "volume": "mm^3", "pressure": "kPa", "phase": "-"}


def write_results_file(path, timeseries, summary=None, fields=None,
                       parameters="subsection Time\n  set end time = 1\nend\n"):
    """Write a results file in the layout of the C++ writer (see systole_post.results).

    Args:
        path: file to create.
        timeseries: column name -> sequence of values (lengths may differ on purpose).
        summary: optional column name -> per-beat values.
        fields: optional step number -> time; creates /fields/step_NNNNNN groups.
        parameters: the parameter text.
    """
    with h5py.File(path, "w") as h5file:
        params = h5file.create_dataset("parameters", data=parameters,
                                       dtype=h5py.string_dtype("utf-8"))
        params.attrs["code_version"] = "0.1.0-test"
        params.attrs["n_ranks"] = np.int32(2)
        for group_name, columns in (("timeseries", timeseries), ("summary", summary)):
            if columns is None:
                continue
            group = h5file.create_group(group_name)
            for name, values in columns.items():
                dataset = group.create_dataset(name, data=np.asarray(values, dtype=np.float64))
                dataset.attrs["unit"] = UNITS.get(name, "-")
        mesh = h5file.create_group("mesh")
        mesh.create_dataset("nodes", data=np.zeros((8, 3)))
        mesh.create_dataset("cells", data=np.arange(8, dtype=np.int64).reshape(1, 8))
        for step, time in (fields or {}).items():
            group = h5file.create_group(f"fields/step_{step:06d}")
            group.attrs["time"] = time
            group.attrs["step"] = step
            group.create_dataset("displacement", data=np.zeros((8, 3)))
    return path


@pytest.fixture
def make_results(tmp_path):
    """Factory fixture: ``make_results(timeseries, name="results.h5", **kw)`` -> path in tmp_path."""

    def make(timeseries, name="results.h5", **kwargs):
        return write_results_file(tmp_path / name, timeseries, **kwargs)

    return make


@pytest.fixture
def three_steps():
    """A small, valid time series of three steps."""
    return {
        "time": [0.0, 0.5, 1.0],
        "step": [0, 1, 2],
        "volume": [1000.0, 1010.5, 1020.25],
        "pressure": [0.0, 0.25, 0.5],
        "phase": [0, 0, 1],
    }
