"""The XDMF files open with VTK's XDMF reader (the one ParaView uses): every field of the
last step equals the HDF5 datasets, for a heartbeat, a Land problem and the EP slab. And in
ParaView itself (pvpython under xvfb-run, through scripts/paraview_load.py): every field of
every step, and a rendered picture.

Needs SYSTOLE_APP (the built systole: the Land and EP runs are made here, with field
output), SYSTOLE_XDMF_HEARTBEAT (a heartbeat's results folder with fields, from ctest) and
SYSTOLE_XDMF_LAND_TET (run.land_problem2_tet's results folder: Land problem 2 on the shipped
tetrahedral ventricle, its fields every 5th step); set by the ctest entry run.pytest_runs.
Skips without them unless SYSTOLE_REQUIRE_APP. The ParaView tests skip without pvpython or
xvfb-run (systole_post.pvpython finds them) unless SYSTOLE_REQUIRE_PARAVIEW.
"""

import os
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from systole_post.pvpython import missing_message, pvpython_command

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
    app = os.path.abspath(need("SYSTOLE_APP"))
    prm = tmp_path / prm_name
    text = re.sub(r"set Field output interval\s*=\s*\d+", "set Field output interval = 5",
                  (RUNS / prm_name).read_text())
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


@pytest.fixture(scope="module")
def land_run(tmp_path_factory):
    return run_with_fields("land_problem2_coarse.prm", tmp_path_factory.mktemp("land"))


@pytest.fixture(scope="module")
def ep_slab_run(tmp_path_factory):
    return run_with_fields("ep_slab_coarse.prm", tmp_path_factory.mktemp("ep_slab"))


def test_land_problem_xdmf_reads_every_field_of_the_last_step(land_run):
    assert "displacement" in check_xdmf(land_run)


def test_ep_slab_xdmf_reads_every_field_of_the_last_step(ep_slab_run):
    assert "transmembrane_potential" in check_xdmf(ep_slab_run)


def pvpython():
    """The command that runs pvpython without a display (xvfb-run), or skip; fail under
    SYSTOLE_REQUIRE_PARAVIEW (scripts/test sets it: its set-up installs pvpython)."""
    command = pvpython_command()
    if command is None:
        if os.environ.get("SYSTOLE_REQUIRE_PARAVIEW"):
            pytest.fail(missing_message())
        pytest.skip(missing_message())
    return command


def check_paraview(folder: Path, field: str, tmp_path: Path):
    """scripts/paraview_load.py in pvpython: every field of every step as ParaView reads it
    equals the HDF5 datasets, and the picture it renders is not blank."""
    script = Path(__file__).resolve().parents[1] / "paraview_load.py"
    dump, picture = tmp_path / "paraview.npz", tmp_path / "paraview.png"
    done = subprocess.run(pvpython() + [str(script), str(folder / "fields.xdmf"), field,
                                        "--dump", str(dump), "--screenshot", str(picture)],
                          capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    read = np.load(dump)
    with h5py.File(folder / "results.h5", "r") as f:
        steps = sorted(f["fields"])
        assert len(read["times"]) == len(steps)
        assert np.array_equal(read["points"], f["mesh/nodes"][()])
        for i, step in enumerate(steps):
            group = f["fields"][step]
            assert np.isclose(read["times"][i], group.attrs["time"])
            names = sorted(k.split("/", 1)[1] for k in read.files if k.startswith(f"{i}/"))
            assert names == sorted(group), step
            for name in names:
                expected = group[name][()]
                values = read[f"{i}/{name}"].reshape(expected.shape)
                assert np.array_equal(values, expected, equal_nan=True), (step, name)
    image = pytest.importorskip("matplotlib.image").imread(picture)
    assert image.shape[:2] == (600, 800) and image[..., :3].std() > 0.05
    return picture


def test_heartbeat_in_paraview_every_field_and_step(tmp_path):
    check_paraview(Path(need("SYSTOLE_XDMF_HEARTBEAT")), "fibre_stretch", tmp_path)


def test_land_problem_in_paraview_every_field_and_step(land_run, tmp_path):
    check_paraview(land_run, "displacement", tmp_path)


def test_ep_slab_in_paraview_every_field_and_step(ep_slab_run, tmp_path):
    check_paraview(ep_slab_run, "transmembrane_potential", tmp_path)


def test_tetrahedral_land_problem_xdmf_reads_every_field_of_the_last_step():
    """Land problem 2 on the shipped tetrahedral ventricle (the run of the ctest entry
    run.land_problem2_tet, fields every 5th step): 4-node tetrahedra, every field."""
    folder = Path(need("SYSTOLE_XDMF_LAND_TET"))
    names = check_xdmf(folder)
    assert "displacement" in names and "pressure" in names
    vtk = pytest.importorskip("vtk")
    reader = vtk.vtkXdmfReader()
    reader.SetFileName(str(folder / "fields.xdmf"))
    reader.Update()
    grid = reader.GetOutputDataObject(0)
    assert {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())} == {vtk.VTK_TETRA}
