"""Tests of systole_post.compare: tolerance rule, failure reports, reference writer, CLI."""

import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import SCRIPTS_DIR
from systole_post import compare
from systole_post.compare import (CompareError, compare_columns, compare_files,
                                  parse_tolerances, read_reference, write_reference)


def write_csv(path, columns):
    """Write a reference CSV by hand (header + rows), independent of write_reference."""
    names = list(columns)
    lines = [",".join(names)]
    lines += [",".join(repr(float(v)) for v in row) for row in zip(*columns.values())]
    path.write_text("\n".join(lines) + "\n")
    return path


# --- tolerance strings -------------------------------------------------------------------

def test_parse_tolerances():
    assert parse_tolerances("volume:1e-8  pressure:2.5e-6\tnewton_iterations:0") == {
        "volume": 1e-8, "pressure": 2.5e-6, "newton_iterations": 0.0}


@pytest.mark.parametrize("text", ["", "   ", "volume", "volume:", "volume:abc", ":1e-8",
                                  "volume:-1e-8", "volume:nan", "volume:inf",
                                  "volume:1 volume:2"])
def test_malformed_tolerances_are_rejected(text):
    with pytest.raises(CompareError):
        parse_tolerances(text)


# --- the rule |a - b| <= tol * max(max|b|, tiny) -----------------------------------------

def test_identical_columns_pass():
    data = {"volume": np.array([1.0, 2.0, 3.0])}
    assert compare_columns(data, {"volume": data["volume"].copy()}, {"volume": 0.0}) == []


def test_tol_zero_rejects_one_ulp_and_accepts_exact():
    b = np.array([1.0, 2.0, 3.0])
    a = b.copy()
    a[1] = np.nextafter(2.0, 3.0)
    assert compare_columns({"n": b.copy()}, {"n": b}, {"n": 0.0}) == []
    failures = compare_columns({"n": a}, {"n": b}, {"n": 0.0})
    assert len(failures) == 1 and "row 1" in failures[0]


def test_tolerance_is_relative_to_the_column_scale_not_the_value():
    # Column scale 1000, tol 1e-8 -> allowed 1e-5 at every row, including where b = 0.
    b = np.array([0.0, 500.0, 1000.0])
    assert compare_columns({"p": b + [9e-6, -9e-6, 9e-6]}, {"p": b}, {"p": 1e-8}) == []
    failures = compare_columns({"p": b + [1.1e-5, 0.0, 0.0]}, {"p": b}, {"p": 1e-8})
    assert len(failures) == 1 and "row 0" in failures[0]


def test_difference_equal_to_the_allowed_one_passes():
    b = np.array([0.0, 4.0])  # tol 0.5 x scale 4 = allowed 2, exact in binary
    assert compare_columns({"p": np.array([2.0, 4.0])}, {"p": b}, {"p": 0.5}) == []
    above = np.array([np.nextafter(2.0, 3.0), 4.0])
    assert compare_columns({"p": above}, {"p": b}, {"p": 0.5}) != []


def test_scale_uses_the_largest_magnitude_including_negative_values():
    b = np.array([-1000.0, 1.0])  # scale 1000 although max(b) = 1
    assert compare_columns({"q": b + [0.0, 9e-6]}, {"q": b}, {"q": 1e-8}) == []
    assert compare_columns({"q": b + [0.0, 2e-5]}, {"q": b}, {"q": 1e-8}) != []


def test_each_column_uses_its_own_scale_and_tolerance():
    results = {"volume": np.array([1000.0 + 5e-6]), "pressure": np.array([1.0 + 5e-6])}
    reference = {"volume": np.array([1000.0]), "pressure": np.array([1.0])}
    failures = compare_columns(results, reference, {"volume": 1e-8, "pressure": 1e-8})
    assert len(failures) == 1 and "'pressure'" in failures[0]
    assert compare_columns(results, reference, {"volume": 1e-8, "pressure": 1e-5}) == []


def test_all_zero_reference_column_is_compared_exactly():
    zeros = np.zeros(3)
    assert compare_columns({"f": zeros.copy()}, {"f": zeros}, {"f": 1e-3}) == []
    assert compare_columns({"f": np.array([0.0, 1e-200, 0.0])}, {"f": zeros}, {"f": 1e-3}) != []


def test_nan_in_results_fails_and_nan_matches_nan():
    b = np.array([1.0, 2.0])
    assert compare_columns({"v": np.array([1.0, np.nan])}, {"v": b}, {"v": 1.0}) != []
    nan_b = np.array([1.0, np.nan])
    assert compare_columns({"v": nan_b.copy()}, {"v": nan_b}, {"v": 0.0}) == []


def test_columns_not_in_the_tolerance_list_are_ignored():
    results = {"volume": np.array([1.0]), "wall_time": np.array([3.0])}
    reference = {"volume": np.array([1.0]), "wall_time": np.array([7.0])}
    assert compare_columns(results, reference, {"volume": 0.0}) == []


def test_different_row_counts_fail_even_if_common_rows_agree():
    failures = compare_columns({"v": np.array([1.0, 2.0])}, {"v": np.array([1.0, 2.0, 3.0])},
                               {"v": 1e-8})
    assert failures == ["row count differs: results have 2, reference has 3"]


@pytest.mark.parametrize("side", ["results", "reference"])
def test_missing_column_fails(side):
    present = {"volume": np.array([1.0]), "pressure": np.array([2.0])}
    absent = {"volume": np.array([1.0])}
    results, reference = (absent, present) if side == "results" else (present, absent)
    failures = compare_columns(results, reference, {"volume": 0.0, "pressure": 0.0})
    assert failures == [f"column 'pressure' missing from the {side}"]


def test_report_names_column_row_value_reference_and_allowed_difference():
    failures = compare_columns({"volume": np.array([10.0, 10.5])},
                               {"volume": np.array([10.0, 20.0])}, {"volume": 1e-3})
    assert len(failures) == 1
    line = failures[0]
    for part in ("'volume'", "row 1", "line 3", "value 10.5", "reference 20",
                 "|difference| 9.5", "allowed 0.02", "tol 0.001"):
        assert part in line, (part, line)


def test_report_is_limited_per_column():
    b = np.zeros(compare.MAX_REPORTED_ROWS + 5)
    failures = compare_columns({"x": b + 1.0}, {"x": b}, {"x": 0.0})
    assert len(failures) == compare.MAX_REPORTED_ROWS + 1
    assert failures[-1] == "column 'x': 5 more rows outside tolerance"


# --- files ---------------------------------------------------------------------------------

def test_compare_files_pass_and_fail(make_results, three_steps, tmp_path):
    results = make_results(three_steps)
    reference = write_csv(tmp_path / "ref.csv", {"volume": three_steps["volume"],
                                                 "pressure": three_steps["pressure"]})
    assert compare_files(results, reference, "volume:0 pressure:0") == []
    three_steps["pressure"][2] += 1e-3
    changed = make_results(three_steps, name="changed.h5")
    failures = compare_files(changed, reference, "volume:0 pressure:1e-8")
    assert len(failures) == 1 and "'pressure' row 2" in failures[0]


def test_read_reference_rejects_ragged_and_non_numeric_rows(tmp_path):
    ragged = tmp_path / "ragged.csv"
    ragged.write_text("a,b\n1,2\n3\n")
    with pytest.raises(CompareError, match="line 3"):
        read_reference(ragged)
    text = tmp_path / "text.csv"
    text.write_text("a,b\n1,two\n")
    with pytest.raises(CompareError, match="non-numeric"):
        read_reference(text)
    with pytest.raises(CompareError, match="cannot read"):
        read_reference(tmp_path / "absent.csv")


def test_write_reference_round_trip_is_bit_exact(make_results, tmp_path):
    awkward = [0.1 + 0.2, 1.0 / 3.0, -1e-300, 6.02214076e23, -0.0]
    path = make_results({"time": [0.0, 1.0, 2.0, 3.0, 4.0], "volume": awkward,
                         "pressure": [5.0, 4.0, 3.0, 2.0, 1.0]})
    csv_path = tmp_path / "reference.csv"
    write_reference(path, csv_path, ["volume", "time"])
    assert csv_path.read_text().splitlines()[0] == "volume,time"
    reference = read_reference(csv_path)
    assert list(reference) == ["volume", "time"]
    assert reference["volume"].tobytes() == np.array(awkward).tobytes()
    assert compare_files(path, csv_path, "volume:0 time:0") == []


def test_write_reference_rejects_unknown_and_empty_columns(make_results, three_steps, tmp_path):
    path = make_results(three_steps)
    with pytest.raises(CompareError, match="no time-series column"):
        write_reference(path, tmp_path / "r.csv", ["volume", "flux"])
    with pytest.raises(CompareError, match="no columns"):
        write_reference(path, tmp_path / "r.csv", [])
    assert not (tmp_path / "r.csv").exists()


# --- command line --------------------------------------------------------------------------

def test_cli_write_then_compare(make_results, three_steps, tmp_path, capsys):
    results = str(make_results(three_steps))
    reference = str(tmp_path / "ref.csv")
    assert compare.main(["--write", results, reference, "volume", "pressure"]) == 0
    assert compare.main([results, reference, "volume:1e-8 pressure:0"]) == 0
    assert "PASS" in capsys.readouterr().out

    three_steps["volume"][0] = 1001.0
    changed = str(make_results(three_steps, name="changed.h5"))
    assert compare.main([changed, reference, "volume:1e-8", "pressure:0"]) == 1
    out = capsys.readouterr().out
    assert "FAIL" in out and "'volume' row 0" in out


def test_cli_reports_unreadable_input(tmp_path, capsys):
    assert compare.main([str(tmp_path / "none.h5"), str(tmp_path / "r.csv"), "v:0"]) == 1
    assert "no such results file" in capsys.readouterr().err


def test_cli_runs_as_module(make_results, three_steps, tmp_path):
    results = str(make_results(three_steps))
    reference = write_csv(tmp_path / "ref.csv", {"volume": three_steps["volume"]})
    env = dict(os.environ, PYTHONPATH=str(SCRIPTS_DIR))
    command = [sys.executable, "-m", "systole_post.compare", results, str(reference)]
    passed = subprocess.run(command + ["volume:0"], cwd=tmp_path, env=env,
                            capture_output=True, text=True)
    assert passed.returncode == 0, passed.stderr
    failed = subprocess.run(command + ["volume:0 pressure:0"], cwd=tmp_path, env=env,
                            capture_output=True, text=True)
    assert failed.returncode == 1
    assert "column 'pressure' missing from the reference" in failed.stdout
