"""Tests of scripts/plot_purkinje_ecg.py and scripts/ecg_electrodes.py (outputs in tmp_path)."""

import subprocess
import sys

import h5py
import numpy as np

from conftest import SCRIPTS_DIR

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
LEADS = ["I", "II", "III", "aVR", "aVL", "aVF", "V1", "V2", "V3", "V4", "V5", "V6"]


def write_file(path, tree=True, ecg=True):
    """A Y-shaped tree of 4 nodes and a 12-lead bump of 20 ms."""
    with h5py.File(path, "w") as f:
        if tree:
            nodes = np.array([[0, 0, 0], [0, 0, -5], [3, 0, -9], [-3, 0, -9.0]])
            for i, c in enumerate("xyz"):
                f.create_dataset(f"purkinje/nodes/{c}", data=nodes[:, i])
            f.create_dataset("purkinje/nodes/activation_time", data=[1.0, 2.7, 4.3, 4.3])
            f.create_dataset("purkinje/nodes/junction", data=[0, 0, 1, 1.0])
            f.create_dataset("purkinje/edges/parent", data=[0, 1, 1.0])
            f.create_dataset("purkinje/edges/child", data=[1, 2, 3.0])
        t = np.arange(0, 60.0)
        f.create_dataset("timeseries/time", data=t)
        if ecg:
            bump = np.where((t > 10) & (t < 30), np.sin(np.pi * (t - 10) / 20) ** 2, 0)
            for k, lead in enumerate(LEADS):
                f.create_dataset(f"timeseries/ecg_{lead}", data=np.cos(k) * bump)
            f.create_dataset("summary/ecg_QRS_onset", data=[10.0])
            f.create_dataset("summary/ecg_QRS_duration", data=[20.0])
    return path


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPTS_DIR / "plot_purkinje_ecg.py"), *args],
                          capture_output=True, text=True)


def test_both_pictures(tmp_path):
    path = write_file(tmp_path / "results.h5")
    out = run(str(path), "-o", str(tmp_path / "x"), "--title", "test")
    assert out.returncode == 0, out.stderr
    for kind in ("tree", "ecg"):
        png = tmp_path / f"x_{kind}.png"
        assert str(png) in out.stdout
        assert png.read_bytes()[:8] == PNG_MAGIC


def test_missing_parts_are_named(tmp_path):
    path = write_file(tmp_path / "results.h5", tree=False)
    out = run(str(path))
    assert out.returncode == 0
    assert "no Purkinje tree" in out.stderr
    assert (tmp_path / "purkinje_ecg.png").is_file()
    assert not (tmp_path / "purkinje_tree.png").exists()
    path = write_file(tmp_path / "empty.h5", tree=False, ecg=False)
    assert run(str(path)).returncode == 1
    assert run(str(tmp_path / "absent.h5")).returncode == 1


def test_electrodes_default_and_rotation():
    import ecg_electrodes

    # The defaults reproduce Electrophysiology / ECG electrodes' default (rounded to mm).
    e = ecg_electrodes.electrodes((0, 0, -40), 0)
    assert np.allclose(np.round(e["V1"]), [100, -25, -37])
    assert np.allclose(np.round(e["LL"]), [-134, -226, -273])
    # The frame is orthonormal: distances between electrodes are kept, and turning the
    # model about its long axis moves no electrode along it.
    body = ecg_electrodes.BODY
    turned = ecg_electrodes.electrodes((15, 0, -8), 45)
    for a, b in (("V1", "V6"), ("RA", "LL"), ("V3", "LA")):
        assert np.isclose(np.linalg.norm(turned[a] - turned[b]),
                          np.linalg.norm(np.subtract(body[a], body[b])))
        assert np.isclose(turned[a][2] - (-8), e[a][2] - (-40))
    frame = ecg_electrodes.model_frame(30)
    assert np.allclose(frame @ frame.T, np.eye(3))
    # The body frame (left, anterior, superior) is left-handed, the model's right-handed:
    # determinant -1 in these coordinates (+1 would place the heart's mirror image).
    assert np.isclose(np.linalg.det(frame), -1)
    # The model's y = z x x in space: with the RV (+x) forwards and the base (+z) up, +y
    # points to the patient's left (the body's +x).
    assert ecg_electrodes.model_frame(0)[1][0] > 0.5
