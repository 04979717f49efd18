"""Compare a results file's time series with a reference CSV, column by column.

Run tests compare numbers, not logs (STYLE.md 2.9). A reference CSV has a header
row of column names and one row per step. Each compared column has its own
tolerance ``tol``, relative to the scale of that reference column::

    |a - b| <= tol * max(max_i |b_i|, tiny)     for every row i

so ``tol = 0`` demands exact equality, and a tolerance of 1e-8 on a pressure
column allows the same absolute error at every step, however small the pressure
is at that step. NaN matches only NaN. A comparison fails when the row counts
differ, a column is missing on either side, or any value is outside tolerance.

Command line (exit status 0 = pass, 1 = fail or unreadable input)::

    python -m systole_post.compare RESULTS.h5 REFERENCE.csv "volume:1e-8 pressure:1e-8"
    python -m systole_post.compare --write RESULTS.h5 REFERENCE.csv volume pressure
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

import numpy as np

from systole_post.results import ResultsError, read_results

#: Floor of a column's scale, so that an all-zero reference column is compared exactly.
TINY = np.finfo(np.float64).tiny

#: At most this many offending rows are listed per column.
MAX_REPORTED_ROWS = 10


class CompareError(Exception):
    """Malformed tolerance string, reference CSV or column list."""


def parse_tolerances(text: str) -> dict[str, float]:
    """Parse ``"volume:1e-8 pressure:1e-8 newton_iterations:0"`` into {column: tol}.

    Raises:
        CompareError: empty text, an entry without ``:``, a tolerance that is not a
            finite number >= 0, or a column given twice.
    """
    tolerances: dict[str, float] = {}
    for entry in text.split():
        name, sep, value = entry.partition(":")
        if not sep or not name:
            raise CompareError(f"tolerance entry '{entry}' is not of the form column:tol")
        try:
            tol = float(value)
        except ValueError:
            raise CompareError(f"tolerance of '{name}' is not a number: '{value}'") from None
        if not math.isfinite(tol) or tol < 0:
            raise CompareError(f"tolerance of '{name}' must be finite and >= 0, got {value}")
        if name in tolerances:
            raise CompareError(f"column '{name}' has two tolerances")
        tolerances[name] = tol
    if not tolerances:
        raise CompareError("no columns to compare (empty tolerance list)")
    return tolerances


def read_reference(csv_path: str | Path) -> dict[str, np.ndarray]:
    """Read a reference CSV (header row, then one row of numbers per step).

    Raises:
        CompareError: missing file, no header, duplicate column, a row with the wrong
            number of fields, or a field that is not a number.
    """
    csv_path = Path(csv_path)
    try:
        with open(csv_path, newline="", encoding="utf-8") as stream:
            rows = [row for row in csv.reader(stream) if row]
    except OSError as error:
        raise CompareError(f"{csv_path}: cannot read reference ({error.strerror})") from None
    if not rows:
        raise CompareError(f"{csv_path}: empty reference file (no header row)")
    header = [name.strip() for name in rows[0]]
    if len(set(header)) != len(header):
        raise CompareError(f"{csv_path}: duplicate column names in header {header}")
    values = np.empty((len(rows) - 1, len(header)))
    for i, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise CompareError(
                f"{csv_path}: line {i + 2} has {len(row)} fields, header has {len(header)}"
            )
        try:
            values[i] = [float(item) for item in row]
        except ValueError:
            raise CompareError(f"{csv_path}: line {i + 2} has a non-numeric field") from None
    return {name: values[:, j].copy() for j, name in enumerate(header)}


def compare_columns(
    results: dict[str, np.ndarray],
    reference: dict[str, np.ndarray],
    tolerances: dict[str, float],
) -> list[str]:
    """Compare the ``tolerances`` columns of ``results`` with ``reference``.

    Rows are compared up to the shorter length even when the lengths differ, so the
    report also shows whether the common part agrees.

    Returns:
        One human-readable line per failure; an empty list means the comparison passed.
        Rows are numbered from 0 (first data row); "line" is the CSV line number.
    """
    failures: list[str] = []
    n_results = len(next(iter(results.values()), ()))
    n_reference = len(next(iter(reference.values()), ()))
    if n_results != n_reference:
        failures.append(f"row count differs: results have {n_results}, reference has {n_reference}")
    for name, tol in tolerances.items():
        if name not in results:
            failures.append(f"column '{name}' missing from the results")
            continue
        if name not in reference:
            failures.append(f"column '{name}' missing from the reference")
            continue
        a = np.asarray(results[name], dtype=np.float64)
        b = np.asarray(reference[name], dtype=np.float64)
        finite_b = np.abs(b[np.isfinite(b)])
        scale = max(float(finite_b.max()) if finite_b.size else 0.0, TINY)
        allowed = tol * scale
        n = min(len(a), len(b))
        a, b = a[:n], b[:n]
        with np.errstate(invalid="ignore"):
            ok = (a == b) | (np.abs(a - b) <= allowed) | (np.isnan(a) & np.isnan(b))
        bad_rows = np.flatnonzero(~ok)
        for row in bad_rows[:MAX_REPORTED_ROWS]:
            failures.append(
                f"column '{name}' row {row} (line {row + 2}): value {a[row]:.17g}, "
                f"reference {b[row]:.17g}, |difference| {abs(a[row] - b[row]):.3g} "
                f"> allowed {allowed:.3g} (tol {tol:g} x column scale {scale:.6g})"
            )
        if len(bad_rows) > MAX_REPORTED_ROWS:
            failures.append(
                f"column '{name}': {len(bad_rows) - MAX_REPORTED_ROWS} more rows outside tolerance"
            )
    return failures


def compare_files(
    results_path: str | Path, csv_path: str | Path, tolerances: str | dict[str, float]
) -> list[str]:
    """Compare a results file with a reference CSV; see :func:`compare_columns`.

    ``tolerances`` is either the string form ``"col:tol ..."`` or a parsed dict.
    """
    if isinstance(tolerances, str):
        tolerances = parse_tolerances(tolerances)
    results = read_results(results_path)
    return compare_columns(results.timeseries, read_reference(csv_path), tolerances)


def write_reference(results_path: str | Path, csv_path: str | Path, columns: list[str]) -> None:
    """Write the given time-series columns of a results file as a reference CSV.

    Values are written with ``repr`` (shortest round-trip form), so reading the CSV
    back gives bit-identical float64 values.

    Raises:
        CompareError: no columns, a column given twice, or a column not in the results.
    """
    results = read_results(results_path)
    if not columns:
        raise CompareError("no columns given for the reference")
    if len(set(columns)) != len(columns):
        raise CompareError(f"duplicate column in {list(columns)}")
    missing = [name for name in columns if name not in results.timeseries]
    if missing:
        raise CompareError(
            f"{results_path}: no time-series column {missing}; "
            f"available: {sorted(results.timeseries)}"
        )
    data = [np.asarray(results.timeseries[name], dtype=np.float64) for name in columns]
    with open(csv_path, "w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow(columns)
        for row in zip(*data):
            writer.writerow([repr(float(value)) for value in row])


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point; returns the exit status (0 pass, 1 fail)."""
    parser = argparse.ArgumentParser(
        prog="python -m systole_post.compare",
        description="Compare time-series columns of a Systole results file with a "
        "reference CSV (|a-b| <= tol * max|reference column|), or write such a CSV.",
    )
    parser.add_argument("--write", action="store_true",
                        help="write REFERENCE.csv from RESULTS.h5 with the given columns")
    parser.add_argument("results", help="results file (HDF5)")
    parser.add_argument("reference", help="reference CSV")
    parser.add_argument("spec", nargs="+",
                        help='tolerances "col:tol ..." (compare) or column names (--write)')
    args = parser.parse_args(argv)
    try:
        if args.write:
            write_reference(args.results, args.reference, args.spec)
            print(f"wrote {args.reference} ({', '.join(args.spec)})")
            return 0
        tolerances = parse_tolerances(" ".join(args.spec))
        failures = compare_files(args.results, args.reference, tolerances)
    except (ResultsError, CompareError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    if failures:
        print(f"FAIL: {args.results} vs {args.reference}")
        for line in failures:
            print(f"  {line}")
        return 1
    print(f"PASS: {args.results} matches {args.reference} in {', '.join(tolerances)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
