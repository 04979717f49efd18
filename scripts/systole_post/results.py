"""Read a Systole results file (HDF5) into plain Python and NumPy objects.

Layout written by the C++ code::

    /parameters                 scalar UTF-8 string (full parameter text);
                                attributes code_version (str), n_ranks (int)
    /timeseries/<column>        1-D float64, one entry per completed step;
                                attribute unit (str); always has time [ms] and step
    /summary/<column>           optional, 1-D, one row per beat; attribute unit
    /mesh/nodes, /mesh/cells    n x 3 float64 [mm], m x 8 int (hexahedra)
    /fields/step_NNNNNN/<name>  optional per-node arrays; attributes time, step
    /statistics/<name>          optional float64 scalars, the cost of the run (wall time,
                                peak memory, timer sections "timer: ...", solver counts);
                                attribute unit; string attributes (discretization, ...)

A run killed midway may leave one column an entry longer than another; the reader
truncates every column of a group to the shortest one and warns.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np


class ResultsError(Exception):
    """A results file is missing, is not HDF5, or lacks a required group."""


@dataclass(frozen=True)
class Results:
    """Contents of one results file (the mesh and field data are not loaded).

    Attributes:
        path: the file that was read.
        parameters: full parameter text ("" if the file has none).
        code_version: version string of the code that wrote the file ("" if absent).
        n_ranks: number of MPI ranks of the run (0 if absent).
        timeseries: column name -> 1-D array; all arrays have the same length. Columns
            are in the file's link order: creation order if the writer tracked it,
            otherwise alphabetical.
        units: column name -> unit string of ``timeseries`` ("" if absent).
        summary: column name -> 1-D array, one row per beat; empty if no /summary.
        summary_units: column name -> unit string of ``summary``.
        field_steps: step numbers of the /fields/step_NNNNNN groups, ascending.
        statistics: name -> value of /statistics (empty if absent).
        statistics_text: string attributes of /statistics (discretization, linear_solver).
    """

    path: Path
    parameters: str
    code_version: str
    n_ranks: int
    timeseries: dict[str, np.ndarray]
    units: dict[str, str]
    summary: dict[str, np.ndarray] = field(default_factory=dict)
    summary_units: dict[str, str] = field(default_factory=dict)
    field_steps: list[int] = field(default_factory=list)
    statistics: dict[str, float] = field(default_factory=dict)
    statistics_text: dict[str, str] = field(default_factory=dict)

    @property
    def n_rows(self) -> int:
        """Number of time-series rows (completed steps)."""
        return len(next(iter(self.timeseries.values()), ()))


def _as_str(value) -> str:
    """Decode an HDF5 string (variable- or fixed-length, str or bytes) to str."""
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8")
    return str(value)


def _read_columns(path: Path, group: h5py.Group) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """Read the 1-D datasets of ``group``, truncated to a common length.

    Returns (columns, units). Warns when the lengths differ (run killed mid-step).
    """
    columns: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for name, dataset in group.items():
        if not isinstance(dataset, h5py.Dataset) or dataset.ndim != 1:
            raise ResultsError(f"{path}: {dataset.name} is not a 1-D dataset")
        columns[name] = dataset[()]
        units[name] = _as_str(dataset.attrs.get("unit", ""))
    lengths = {name: len(values) for name, values in columns.items()}
    if len(set(lengths.values())) > 1:
        shortest = min(lengths.values())
        warnings.warn(
            f"{path}: columns of {group.name} have unequal lengths {lengths}; "
            f"truncating all to {shortest} rows (run stopped mid-step?)",
            stacklevel=3,
        )
        columns = {name: values[:shortest] for name, values in columns.items()}
    return columns, units


def _field_steps(group: h5py.Group | None) -> list[int]:
    """Step numbers of the ``step_NNNNNN`` subgroups of /fields, ascending."""
    if group is None:
        return []
    steps = []
    for name in group:
        prefix, _, number = name.partition("_")
        if prefix == "step" and number.isdigit():
            steps.append(int(number))
    return sorted(steps)


def read_results(path: str | Path) -> Results:
    """Read the parameters, time series, summary and field-step list of a results file.

    Args:
        path: results file written by the ``systole`` application.

    Raises:
        ResultsError: the file does not exist, is not HDF5, or has no /timeseries
            group (the message is one line and names the file).
    """
    path = Path(path)
    if not path.is_file():
        raise ResultsError(f"{path}: no such results file")
    if not h5py.is_hdf5(path):
        raise ResultsError(f"{path}: not an HDF5 file")
    try:
        h5file = h5py.File(path, "r")
    except OSError as error:
        message = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise ResultsError(f"{path}: cannot open HDF5 file ({message})") from error
    with h5file:
        if not isinstance(h5file.get("timeseries"), h5py.Group):
            raise ResultsError(f"{path}: no /timeseries group (not a Systole results file?)")
        timeseries, units = _read_columns(path, h5file["timeseries"])
        summary, summary_units = {}, {}
        if isinstance(h5file.get("summary"), h5py.Group):
            summary, summary_units = _read_columns(path, h5file["summary"])
        statistics, statistics_text = {}, {}
        if isinstance(h5file.get("statistics"), h5py.Group):
            group = h5file["statistics"]
            statistics = {k: float(group[k][()]) for k in group}
            statistics_text = {k: _as_str(v) for k, v in group.attrs.items()}
        parameters = h5file.get("parameters")
        attrs = parameters.attrs if parameters is not None else {}
        return Results(
            path=path,
            parameters=_as_str(parameters[()]) if parameters is not None else "",
            code_version=_as_str(attrs.get("code_version", "")),
            n_ranks=int(attrs.get("n_ranks", 0)),
            timeseries=timeseries,
            units=units,
            summary=summary,
            summary_units=summary_units,
            field_steps=_field_steps(h5file.get("fields")),
            statistics=statistics,
            statistics_text=statistics_text,
        )
