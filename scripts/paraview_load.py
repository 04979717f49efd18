#!/usr/bin/env pvpython
"""Load a Systole run into ParaView with sensible colour maps.

    python -m systole_post.pvpython scripts/paraview_load.py results/<run>/fields.xdmf
        [FIELD] [--screenshot PNG] [--dump NPZ]
    (pvpython under xvfb-run: systole_post.pvpython finds it, e.g. the checkout's
    .paraview/usr/bin/pvpython, run by that absolute path; or, in the ParaView GUI:
    View > Python Shell > Run Script, with sys.argv set)

Opens the XDMF file (every field step, in time), warps the mesh by the displacement, colours
it by FIELD (default: the first present of DEFAULT_ORDER) and gives every known field a
colour map and range convention: strains and stresses diverging about 0, the fibre stretch
and J diverging about 1, activation times sequential. Without a display (no window mapped,
e.g. under xvfb-run) it saves a screenshot of the last step beside the file, or to PNG.
--dump writes what ParaView read, every point field of every time step, to NPZ (keys
"times", "points", "<step>/<field>"): scripts/tests/test_xdmf_vtk.py compares it with h5py.
"""

import sys
from pathlib import Path

#: field -> (ParaView preset, centre of a symmetric range or None for the data range).
COLOUR_MAPS = {
    "strain_circumferential": ("Cool to Warm", 0.0),
    "strain_longitudinal": ("Cool to Warm", 0.0),
    "strain_radial": ("Cool to Warm", 0.0),
    "fibre_stretch": ("Cool to Warm", 1.0),
    "J": ("Cool to Warm", 1.0),
    "first_principal_stress": ("Inferno (matplotlib)", None),
    "fibre_stress": ("Inferno (matplotlib)", None),
    "active_tension": ("Inferno (matplotlib)", None),
    "activation_time": ("Viridis (matplotlib)", None),
    "latest_activation_time": ("Viridis (matplotlib)", None),
    "transmembrane_potential": ("Jet", None),
    "displacement": ("Viridis (matplotlib)", None),
    "pressure": ("Cool to Warm", 0.0),
}
DEFAULT_ORDER = ["strain_circumferential", "activation_time", "fibre_stretch",
                 "transmembrane_potential", "displacement"]


def colour_range(values_range, centre):
    """The range of the colour map: symmetric about centre, or the data range."""
    low, high = values_range
    if centre is None:
        return low, high
    half = max(abs(low - centre), abs(high - centre), 1e-12)
    return centre - half, centre + half


def dump(reader, path):
    """Every point field of every time step as ParaView reads it, to an .npz file."""
    import numpy as np  # noqa: PLC0415 (pvpython's numpy)
    from paraview import servermanager  # noqa: PLC0415
    from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: PLC0415

    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    arrays = {"times": np.array(times)}
    for i, t in enumerate(times):
        reader.UpdatePipeline(t)
        grid = servermanager.Fetch(reader)
        if i == 0:
            arrays["points"] = vtk_to_numpy(grid.GetPoints().GetData())
        data = grid.GetPointData()
        for k in range(data.GetNumberOfArrays()):
            arrays[f"{i}/{data.GetArrayName(k)}"] = vtk_to_numpy(data.GetArray(k))
    np.savez(path, **arrays)


def main(argv):
    from paraview import simple  # noqa: PLC0415 (only under pvpython)

    options = {}
    for flag in ("--screenshot", "--dump"):
        if flag in argv:
            i = argv.index(flag)
            options[flag] = Path(argv[i + 1]).resolve()
            argv = argv[:i] + argv[i + 2:]
    xdmf = Path(argv[1]).resolve()
    reader = simple.XDMFReader(registrationName=xdmf.parent.name, FileNames=[str(xdmf)])
    reader.UpdatePipelineInformation()
    fields = list(reader.PointData.keys())
    source = reader
    if "displacement" in fields:
        source = simple.WarpByVector(Input=reader, Vectors=["POINTS", "displacement"])
    view = simple.GetActiveViewOrCreate("RenderView")
    display = simple.Show(source, view)
    field = argv[2] if len(argv) > 2 else next((f for f in DEFAULT_ORDER if f in fields),
                                               fields[0])
    simple.ColorBy(display, ("POINTS", field))
    # The colour ranges of the last step (the first is often the unloaded state: all 0 or 1).
    reader.UpdatePipeline(reader.TimestepValues[-1] if reader.TimestepValues else 0)
    for name in fields:
        preset, centre = COLOUR_MAPS.get(name, ("Viridis (matplotlib)", None))
        lut = simple.GetColorTransferFunction(name)
        lut.ApplyPreset(preset, True)
        array = reader.PointData[name]
        low, high = colour_range(array.GetRange(-1 if array.GetNumberOfComponents() > 1
                                                else 0), centre)
        lut.RescaleTransferFunction(low, high)
        lut.AutomaticRescaleRangeMode = "Never"
    display.SetScalarBarVisibility(view, True)
    simple.GetScalarBar(simple.GetColorTransferFunction(field), view).RangeLabelFormat = \
        "%-#6.3g"
    simple.GetAnimationScene().UpdateAnimationUsingDataTimeSteps()
    simple.GetAnimationScene().AnimationTime = reader.TimestepValues[-1] \
        if reader.TimestepValues else 0
    # A side view: looking along +y, z up (the ventricles' long axis, the beam's height).
    view.CameraPosition, view.CameraFocalPoint, view.CameraViewUp = [0, -1, 0], [0, 0, 0], \
        [0, 0, 1]
    view.ResetCamera()
    if "--dump" in options:
        dump(reader, options["--dump"])
    if "--screenshot" in options or not view.GetRenderWindow().GetMapped():
        target = options.get("--screenshot", xdmf.with_name(f"{field}.png"))
        simple.SaveScreenshot(str(target), view, ImageResolution=[800, 600])
    simple.Render(view)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(1)
    main(sys.argv)
