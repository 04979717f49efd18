"""Tests of systole_post.results.read_results on tiny files built here."""

import warnings

import h5py
import numpy as np
import pytest

from systole_post.results import ResultsError, read_results


def test_reads_parameters_metadata_and_columns(make_results, three_steps):
    text = "subsection Heart\n  set fibre angle = 60 # degrees, ±60° helix\nend\n"
    path = make_results(three_steps, parameters=text)
    results = read_results(path)
    assert results.parameters == text
    assert results.code_version == "0.1.0-test"
    assert results.n_ranks == 2
    assert sorted(results.timeseries) == sorted(three_steps)
    np.testing.assert_array_equal(results.timeseries["volume"], three_steps["volume"])
    assert results.timeseries["volume"].dtype == np.float64
    assert results.units == {"time": "ms", "step": "-", "volume": "mm^3",
                             "pressure": "kPa", "phase": "-"}
    assert results.n_rows == 3


def test_optional_groups_absent_give_empty_containers(make_results, three_steps):
    results = read_results(make_results(three_steps))
    assert results.summary == {}
    assert results.field_steps == []


def test_reads_summary_and_field_steps(make_results, three_steps):
    path = make_results(three_steps, summary={"beat": [0, 1], "stroke_volume": [70.0, 71.5]},
                        fields={20: 1.0, 0: 0.0, 10: 0.5})
    results = read_results(path)
    np.testing.assert_array_equal(results.summary["stroke_volume"], [70.0, 71.5])
    assert results.summary_units["stroke_volume"] == "-"
    assert results.field_steps == [0, 10, 20]


def test_unequal_column_lengths_are_truncated_with_warning(make_results, three_steps):
    three_steps["volume"] = three_steps["volume"] + [1030.0]  # killed after writing volume
    path = make_results(three_steps)
    with pytest.warns(UserWarning, match="truncating all to 3 rows"):
        results = read_results(path)
    assert {len(values) for values in results.timeseries.values()} == {3}
    np.testing.assert_array_equal(results.timeseries["volume"], [1000.0, 1010.5, 1020.25])


def test_equal_column_lengths_do_not_warn(make_results, three_steps):
    path = make_results(three_steps)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_results(path)


def test_fixed_length_string_attributes_are_decoded(tmp_path):
    path = tmp_path / "fixed.h5"
    with h5py.File(path, "w") as h5file:
        params = h5file.create_dataset("parameters", data=np.bytes_("set a = 1"))
        params.attrs["code_version"] = np.bytes_("abc123")
        params.attrs["n_ranks"] = 1
        h5file.create_dataset("timeseries/time", data=[0.0, 1.0]).attrs["unit"] = np.bytes_("ms")
    results = read_results(path)
    assert results.parameters == "set a = 1"
    assert results.code_version == "abc123"
    assert results.units["time"] == "ms"


def test_missing_file_raises_one_line_error_naming_file(tmp_path):
    path = tmp_path / "nowhere.h5"
    with pytest.raises(ResultsError) as info:
        read_results(path)
    assert str(path) in str(info.value)
    assert "\n" not in str(info.value)


def test_non_hdf5_file_raises(tmp_path):
    path = tmp_path / "log.h5"
    path.write_text("this is a log, not HDF5\n")
    with pytest.raises(ResultsError, match="not an HDF5 file") as info:
        read_results(path)
    assert str(path) in str(info.value)


def test_file_without_timeseries_raises(tmp_path):
    path = tmp_path / "mesh_only.h5"
    with h5py.File(path, "w") as h5file:
        h5file.create_dataset("mesh/nodes", data=np.zeros((8, 3)))
    with pytest.raises(ResultsError, match="no /timeseries") as info:
        read_results(path)
    assert str(path) in str(info.value)


def test_two_dimensional_column_is_rejected(tmp_path):
    path = tmp_path / "bad.h5"
    with h5py.File(path, "w") as h5file:
        h5file.create_dataset("timeseries/time", data=np.zeros((2, 2)))
    with pytest.raises(ResultsError, match="not a 1-D dataset"):
        read_results(path)


def test_reads_statistics_values_and_texts(tmp_path):
    path = tmp_path / "results.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("timeseries/time", data=[0.0, 1.0])
        group = f.create_group("statistics")
        group.create_dataset("wall_time", data=12.5)
        group.create_dataset("timer: Mechanics: assembly", data=3.25)
        group.attrs["discretization"] = np.bytes_("Q2 (displacement, volumetric penalty)")
    results = read_results(path)
    assert results.statistics == {"timer: Mechanics: assembly": 3.25, "wall_time": 12.5}
    assert results.statistics_text == {"discretization": "Q2 (displacement, volumetric penalty)"}
    assert read_results(path).statistics["wall_time"] == 12.5


def test_statistics_of_a_run(tmp_path):
    """The app writes its cost as numbers (a 0D circulation beat: no mesh, a second)."""
    import os
    import subprocess

    app = os.environ.get("SYSTOLE_APP")
    if not app:
        if os.environ.get("SYSTOLE_REQUIRE_APP"):
            pytest.fail("SYSTOLE_APP not set")
        pytest.skip("SYSTOLE_APP (the built systole) not set")
    app = os.path.abspath(app)
    prm = tmp_path / "c.prm"
    prm.write_text("set Problem = circulation\nsubsection Circulation\n"
                   "  set Number of beats = 1\nend\n")
    subprocess.run([app, str(prm)], cwd=tmp_path, check=True, capture_output=True)
    stats = read_results(tmp_path / "results" / "c" / "results.h5").statistics
    assert stats["beats"] == 1 and stats["arkode_steps"] > 0
    assert stats["wall_time"] > 0 and stats["peak_memory_per_rank"] > 0
