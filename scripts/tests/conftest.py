"""Shared pytest setup: tiny results files (scripts/ is on sys.path through pytest.ini)."""

from pathlib import Path

import h5py
import numpy as np
import pytest

SCRIPTS_DIR = Path(__file__).resolve().parent.parent

#: Units of the columns the helper knows; other columns get the unit of their suffix
#: (SUFFIX_UNITS) or "-".
UNITS = {"time": "ms", "step": "-", "volume": "mm^3", "pressure": "kPa", "phase": "-",
         "start_time": "ms", "end_time": "ms"}
SUFFIX_UNITS = (("_mL_per_s", "mL/s"), ("_mmHg", "mmHg"), ("_mL", "mL"))


def unit_of(name):
    """The unit the helper writes for column ``name``."""
    if name in UNITS:
        return UNITS[name]
    return next((unit for suffix, unit in SUFFIX_UNITS if name.endswith(suffix)), "-")


def write_results_file(path, timeseries, summary=None, fields=None, events=None,
                       parameters="subsection Time\n  set end time = 1\nend\n",
                       track_order=False):
    """Write a results file in the layout of the C++ writer (see systole_post.results).

    Args:
        path: file to create.
        timeseries: column name -> sequence of values (lengths may differ on purpose).
        summary: optional column name -> per-beat values.
        fields: optional step number -> time; creates /fields/step_NNNNNN groups.
        events: optional column name -> per-event values (/events).
        parameters: the parameter text.
        track_order: keep the columns in creation order, as the C++ writer does (else
            HDF5 lists them alphabetically).
    """
    with h5py.File(path, "w", track_order=track_order) as h5file:
        params = h5file.create_dataset("parameters", data=parameters,
                                       dtype=h5py.string_dtype("utf-8"))
        params.attrs["code_version"] = "0.1.0-test"
        params.attrs["n_ranks"] = np.int32(2)
        for group_name, columns in (("timeseries", timeseries), ("summary", summary),
                                    ("events", events)):
            if columns is None:
                continue
            group = h5file.create_group(group_name, track_order=track_order)
            for name, values in columns.items():
                dataset = group.create_dataset(name, data=np.asarray(values, dtype=np.float64))
                dataset.attrs["unit"] = unit_of(name)
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
