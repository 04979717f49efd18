"""The AHA bull's-eye: one wedge per segment where the bull's-eye convention puts it, in
the colour of its value, written as a PNG."""

import matplotlib
import numpy as np
from conftest import write_results_file
from matplotlib.colors import Normalize

from systole_post.bullseye import QUANTITIES, make_bullseye_figure, segment_wedges
from systole_post.results import read_results


def aha_summary(values):
    summary = {"beat": [0.0]}
    for n in range(1, 18):
        for quantity in QUANTITIES:
            summary[f"aha_{n:02d}_{quantity}"] = [values[n - 1]]
    return summary


def test_segments_tile_the_disc_in_the_bulls_eye_order():
    wedges = segment_wedges()
    assert len(wedges) == 17
    # Basal anterior (1) and mid anterior (7) centred at the top, the anteroseptal ones
    # (2, 8) 60 degrees counter-clockwise, i.e. towards the septum on the left.
    for n, centre in ((1, 90), (2, 150), (4, 270), (7, 90), (13, 90), (14, 180)):
        start, width, _, _ = wedges[n - 1]
        assert np.isclose(np.degrees(start + width / 2) % 360, centre)
    rings = [(w[2], w[3]) for w in wedges]
    assert rings[:6] == [(3, 4)] * 6 and rings[6:12] == [(2, 3)] * 6
    assert rings[12:16] == [(1, 2)] * 4 and rings[16] == (0, 1)
    # The wedges of each ring cover 360 degrees.
    for ring in ((0, 6), (6, 12), (12, 16), (16, 17)):
        assert np.isclose(sum(w[1] for w in wedges[ring[0]:ring[1]]), 2 * np.pi)


def test_bullseye_png_has_each_segment_in_the_colour_of_its_value(tmp_path):
    values = np.linspace(-0.2, 0.14, 17)
    values[4] = np.nan
    path = tmp_path / "results.h5"
    write_results_file(path, {"time": [0.0], "step": [0.0]}, summary=aha_summary(values))
    figure = make_bullseye_figure(read_results(path))
    png = tmp_path / "bullseye.png"
    figure.savefig(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10000
    strain_axes = figure.axes[0]
    bars = [p for p in strain_axes.patches]
    assert len(bars) == 17
    bound = np.nanmax(np.abs(values))
    norm, cmap = Normalize(-bound, bound), matplotlib.colormaps["RdBu_r"]
    for n, bar in enumerate(bars, start=1):
        expected = (0.8, 0.8, 0.8, 1.0) if np.isnan(values[n - 1]) else cmap(norm(values[n - 1]))
        assert np.allclose(bar.get_facecolor(), expected), n
    # The pixels: the picture is not blank (many colours).
    image = matplotlib.image.imread(png)
    colours = np.unique((image[..., :3] * 255).astype(int).reshape(-1, 3), axis=0)
    assert len(colours) > 50
