"""The XDMF files open with VTK's XDMF reader (the one ParaView uses): every field of the
last step equals the HDF5 datasets, for a heartbeat, a Land problem and the EP slab.

Needs SYSTOLE_APP (the built systole: the Land and EP runs are made here, with field
output) and SYSTOLE_XDMF_HEARTBEAT (a heartbeat's results folder with fields, from ctest);
set by the ctest entry run.pytest_runs. Skips without them unless SYSTOLE_REQUIRE_APP.
"""

import os
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

RUNS = Path(__file__).resolve().parents[2] / "tests" / "runs"


def need(variable):
    value = os.environ.get(variable)
    if not value:
        if os.environ.get("SYSTOLE_REQUIRE_APP"):
            pytest.fail(f"{variable} not set")
        pytest.skip(f"{variable} not set")
    return value


def run_with_fields(prm_name, tmp_path):
    """Run tests/runs/<prm_name> with fields at every 5th step; its results folder."""
    prm = tmp_path / prm_name
    prm.write_text((RUNS / prm_name).read_text())
    return run_with_fields_of(prm, tmp_path)


def run_with_fields_of(prm, tmp_path):
    """Run the parameter file prm (in tmp_path) with fields at every 5th step; its results
    folder."""
    app = os.path.abspath(need("SYSTOLE_APP"))
    text = re.sub(r"set Field output interval\s*=\s*\d+", "set Field output interval = 5",
                  prm.read_text())
    prm.write_text(text)
    subprocess.run([app, str(prm)], cwd=tmp_path, check=True, capture_output=True,
                   timeout=300)
    return tmp_path / "results" / prm.stem


def check_xdmf(folder: Path):
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXdmfReader()
    reader.SetFileName(str(folder / "fields.xdmf"))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(
        vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    with h5py.File(folder / "results.h5", "r") as f:
        steps = sorted(f["fields"])
        last = f["fields"][steps[-1]]
        assert len(times) == len(steps)
        assert np.isclose(times[-1], last.attrs["time"])
        reader.UpdateTimeStep(times[-1])
        grid = reader.GetOutputDataObject(0)
        assert grid.GetNumberOfCells() == f["mesh/cells"].shape[0]
        points = vtk_to_numpy(grid.GetPoints().GetData())
        assert np.array_equal(points, f["mesh/nodes"][()])
        data = grid.GetPointData()
        names = sorted(data.GetArrayName(i) for i in range(data.GetNumberOfArrays()))
        assert names == sorted(last)
        for name in names:
            expected = last[name][()]
            values = vtk_to_numpy(data.GetArray(name)).reshape(expected.shape)
            assert np.array_equal(values, expected, equal_nan=True), name
    return names


def test_heartbeat_xdmf_reads_every_field_of_the_last_step():
    names = check_xdmf(Path(need("SYSTOLE_XDMF_HEARTBEAT")))
    for name in ("displacement", "fibre_stretch", "strain_circumferential", "J"):
        assert name in names


def test_land_problem_xdmf_reads_every_field_of_the_last_step(tmp_path):
    assert "displacement" in check_xdmf(run_with_fields("land_problem2_coarse.prm", tmp_path))


def test_ep_slab_xdmf_reads_every_field_of_the_last_step(tmp_path):
    names = check_xdmf(run_with_fields("ep_slab_coarse.prm", tmp_path))
    assert "transmembrane_potential" in names


def test_tetrahedral_land_problem_xdmf_reads_every_field_of_the_last_step(tmp_path):
    """Land problem 2 on the shipped tetrahedral ventricle: 4-node tetrahedra, every field."""
    prm = tmp_path / "land_problem2_tet.prm"
    text = (RUNS / prm.name).read_text()
    mesh = re.search(r"set Mesh file\s*=\s*(\S+)", text).group(1)
    prm.write_text(text.replace(mesh, str((RUNS / mesh).resolve())))
    names = check_xdmf(run_with_fields_of(prm, tmp_path))
    assert "displacement" in names and "pressure" in names
    vtk = pytest.importorskip("vtk")
    reader = vtk.vtkXdmfReader()
    reader.SetFileName(str(tmp_path / "results" / prm.stem / "fields.xdmf"))
    reader.Update()
    grid = reader.GetOutputDataObject(0)
    assert {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())} == {vtk.VTK_TETRA}
