"""scripts/report.py: a self-contained HTML page; it renders in headless Chromium without
network, with every picture decoded.

The run-backed tests use SYSTOLE_REPORT_RESULTS (a heartbeat's results.h5, set by the ctest
entry run.pytest_runs) and skip without it unless SYSTOLE_REQUIRE_APP is set.
"""

import os
import re
import shutil
import subprocess
from pathlib import Path

import matplotlib.figure
import matplotlib.image
import numpy as np
import pytest
from test_bullseye import aha_summary

from conftest import write_results_file
from report import (ECG_GRID, build_report, clinical_figure, clinical_rows, ecg_figure,
                    write_report)
from systole_post.results import read_results


def synthetic(tmp_path):
    path = tmp_path / "run" / "results.h5"
    path.parent.mkdir()
    t = np.linspace(0, 800, 41)
    write_results_file(path, {"time": t, "step": np.arange(41.0),
                              "torsion": 10 * np.sin(t / 800 * np.pi),
                              "long_axis_shortening": 0.1 * np.sin(t / 800 * np.pi)},
                       summary=aha_summary(np.linspace(-0.2, 0.1, 17)))
    return path


def test_report_embeds_its_pictures_and_names_no_url(tmp_path):
    path = synthetic(tmp_path)
    text = build_report(path)
    assert text.count('src="data:image/png;base64,') == 2  # global indices, AHA
    assert not re.search(r'(src|href)="(https?:|//)', text)
    assert "AHA segments" in text and "Parameters" in text
    assert write_report(path) == path.parent / "report.html"


def test_report_embeds_the_paraview_picture_beside_the_results(tmp_path):
    path = synthetic(tmp_path)
    assert "<h2>ParaView</h2>" not in build_report(path)
    figure = matplotlib.figure.Figure(figsize=(2, 1))
    figure.subplots().plot([0, 1], [1, 0])
    figure.savefig(path.parent / "paraview.png")
    text = build_report(path)
    assert "<h2>ParaView</h2>" in text
    assert text.count('src="data:image/png;base64,') == 3


def test_report_shows_the_clinical_peaks_against_the_normal_ranges(tmp_path):
    path = tmp_path / "run" / "results.h5"
    path.parent.mkdir()
    t = np.linspace(0, 800, 41)
    summary = {"beat": [0.0, 1.0],
               "peak_global_longitudinal_strain": [0.05, -0.2],  # positive: outside
               "peak_global_radial_strain": [0.3, 0.7],  # +30 % in, +70 % out
               "peak_twist": [40.0, 12.0],
               "peak_apex_displacement": [4.0, 6.0],  # < 5 mm
               "peak_torsion_per_length": [0.1, 0.2]}  # no range
    write_results_file(path, {"time": t, "step": np.arange(41.0),
                              "global_longitudinal_strain": -0.1 * np.sin(t / 800 * np.pi),
                              "twist": 10 * np.sin(t / 800 * np.pi)},
                       summary=summary)
    rows = {label: (values, band, inside)
            for label, values, band, inside, _ in clinical_rows(read_results(path))}
    assert list(rows) == ["global longitudinal strain (GLS) [%]",
                          "global radial strain (GRS) [%]", "twist (apex minus base) [deg]",
                          "torsion (twist per ED length) [deg/mm]",
                          "apex displacement [mm]"]
    values, band, inside = rows["global longitudinal strain (GLS) [%]"]
    assert values == pytest.approx([5.0, -20.0]) and band == "-24 … -16 %"
    assert inside == [False, True]
    assert rows["global radial strain (GRS) [%]"][2] == [True, False]
    assert rows["twist (apex minus base) [deg]"][2] == [False, True]
    assert rows["apex displacement [mm]"][1:] == ("< 5 mm", [True, False])
    assert rows["torsion (twist per ED length) [deg/mm]"][1:] == ("", [None, None])
    text = build_report(path)
    assert "<h2>Clinical kinematics</h2>" in text
    assert text.count('class="out"') == 4 and text.count('class="in"') == 4
    # One figure: the traces of the columns it has (GLS, twist).
    assert text.count('src="data:image/png;base64,') == 1
    assert len(clinical_figure(read_results(path)).axes) == 2


def test_report_shows_the_12_leads_on_the_usual_grid(tmp_path):
    path = tmp_path / "run" / "results.h5"
    path.parent.mkdir()
    t = np.linspace(0, 400, 201)
    leads = [lead for row in ECG_GRID for lead in row]
    columns = {"time": t, "step": np.arange(201.0)}
    for k, lead in enumerate(leads):
        columns[f"ecg_{lead}"] = (k + 1) * np.exp(-((t - 40) / 10) ** 2)
    write_results_file(path, columns, summary={"beat": [0.0], "ecg_QRS_duration": [62.5]})
    figure = ecg_figure(read_results(path))
    assert len(figure.axes) == 12
    # Rows of limb, augmented and precordial leads, each panel its lead's trace.
    assert [ax.get_title(loc="left") for ax in figure.axes] == [
        "I", "aVR", "V1", "V4", "II", "aVL", "V2", "V5", "III", "aVF", "V3", "V6"]
    for ax in figure.axes:
        k = leads.index(ax.get_title(loc="left"))
        assert np.max(ax.lines[0].get_ydata()) == pytest.approx(k + 1, rel=1e-3)
    text = build_report(path)
    assert "<h2>ECG</h2>" in text and "ecg_QRS_duration" in text
    assert text.count('src="data:image/png;base64,') == 1
    # Without one lead there is no ECG section.
    del columns["ecg_V6"]
    other = tmp_path / "other" / "results.h5"
    other.parent.mkdir()
    write_results_file(other, columns)
    assert ecg_figure(read_results(other)) is None
    assert "<h2>ECG</h2>" not in build_report(other)


def test_report_without_clinical_columns_has_no_such_section(tmp_path):
    text = build_report(synthetic(tmp_path))
    assert "Clinical kinematics" not in text


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    if os.environ.get("SYSTOLE_REQUIRE_APP"):
        pytest.fail("no headless Chromium (Debian package chromium; scripts/lib/setup.sh)")
    pytest.skip("no Chromium")


def render(html: Path, tmp_path: Path):
    """(DOM after load, screenshot) of the page in headless Chromium with the network
    blocked (every host unresolvable, a dead proxy)."""
    flags = [chromium(), "--headless=new", "--no-sandbox", "--disable-gpu",
             "--proxy-server=http://127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND",
             f"--user-data-dir={tmp_path / 'profile'}"]
    url = html.resolve().as_uri()
    dom = subprocess.run(flags + ["--virtual-time-budget=5000", "--dump-dom", url],
                         capture_output=True, text=True, timeout=120).stdout
    shot = tmp_path / "shot.png"
    subprocess.run(flags + ["--window-size=1400,4000", f"--screenshot={shot}", url],
                   capture_output=True, timeout=120, check=True)
    return dom, shot


def check_rendered(html: Path, tmp_path: Path, n_pictures: int):
    dom, shot = render(html, tmp_path)
    assert f'data-pictures="{n_pictures}/{n_pictures}"' in dom
    sizes = re.findall(r'data-decoded="(\d+)x(\d+)"', dom)
    assert len(sizes) == n_pictures and all(int(w) > 100 and int(h) > 100 for w, h in sizes)
    image = matplotlib.image.imread(shot)
    colours = np.unique((image[..., :3] * 255).astype(int).reshape(-1, 3), axis=0)
    assert len(colours) > 200  # plots, not a blank page


def test_synthetic_report_renders_in_headless_chromium(tmp_path):
    html = write_report(synthetic(tmp_path))
    check_rendered(html, tmp_path, 2)


def test_heartbeat_report_renders_with_every_section(tmp_path):
    results = os.environ.get("SYSTOLE_REPORT_RESULTS")
    if not results:
        if os.environ.get("SYSTOLE_REQUIRE_APP"):
            pytest.fail("SYSTOLE_REPORT_RESULTS not set")
        pytest.skip("SYSTOLE_REPORT_RESULTS (a heartbeat's results.h5) not set")
    html = write_report(results, tmp_path / "report.html")
    text = html.read_text()
    for title in ("Provenance", "Pressure-volume loop", "Traces", "Global indices",
                  "Clinical kinematics", "Activation map", "ECG", "AHA segments", "Beats",
                  "Cost", "Parameters"):
        assert f"<h2>{title}</h2>" in text, title
    assert "code version" in text and "wall time" in text
    check_rendered(html, tmp_path, 7)


def test_paraview_script_has_a_colour_map_for_every_postprocessor_field():
    import paraview_load

    for name in ("fibre_stretch", "active_tension", "first_principal_stress", "fibre_stress",
                 "strain_circumferential", "strain_longitudinal", "strain_radial", "J",
                 "activation_time", "displacement"):
        assert name in paraview_load.COLOUR_MAPS
    assert paraview_load.colour_range((-0.1, 0.3), 0.0) == (-0.3, 0.3)
    assert paraview_load.colour_range((0.9, 1.05), 1.0) == pytest.approx((0.9, 1.1))
    assert paraview_load.colour_range((2.0, 5.0), None) == (2.0, 5.0)
