"""Tests of systole_post.fibres and scripts/plot_fibres.py (outputs go to tmp_path)."""

import subprocess
import sys

import numpy as np
import pytest

from conftest import SCRIPTS_DIR
from systole_post.fibres import helix_profile, make_helix_profile_figure, plot_helix_profile
from systole_post.results import read_results

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture
def fibre_results(make_results):
    """A systole-fibres results file: helix angle 60 -> -60 degrees in 4 bins, one empty."""
    lower = np.array([0.0, 0.25, 0.5, 0.75])
    mean = 60.0 - 120.0 * (lower + 0.125)
    summary = {
        "depth_lower": lower,
        "depth_upper": lower + 0.25,
        "depth": lower + 0.125,
        "helix_mean": np.where(lower == 0.5, np.nan, mean),
        "helix_min": np.where(lower == 0.5, np.nan, mean - 15.0),
        "helix_max": np.where(lower == 0.5, np.nan, mean + 15.0),
        "n_points": np.where(lower == 0.5, 0.0, 100.0),
    }
    timeseries = {"step": [0], "time": [0.0], "n_cells": [20], "n_points": [300]}
    return make_results(timeseries, summary=summary)


def test_profile_skips_empty_bins(fibre_results):
    profile = helix_profile(read_results(fibre_results))
    assert list(profile["depth"]) == [0.125, 0.375, 0.875]
    assert list(profile["helix_mean"]) == [45.0, 15.0, -45.0]


def test_figure_shows_mean_against_depth(fibre_results):
    figure = make_helix_profile_figure(read_results(fibre_results))
    ax = figure.axes[0]
    assert ax.get_ylabel() == "helix angle [degree]"
    assert ax.get_xlabel().startswith("transmural depth")
    mean_line = [line for line in ax.get_lines() if line.get_label() == "mean"][0]
    assert list(mean_line.get_xdata()) == [0.125, 0.375, 0.875]
    assert list(mean_line.get_ydata()) == [45.0, 15.0, -45.0]


def test_plot_writes_png(fibre_results, tmp_path):
    out = plot_helix_profile(fibre_results, tmp_path / "helix.png")
    assert out.read_bytes()[:8] == PNG_MAGIC


def test_file_without_profile_raises(make_results, three_steps):
    with pytest.raises(ValueError, match="no helix-angle profile"):
        helix_profile(read_results(make_results(three_steps)))


def test_script_output_option(fibre_results, tmp_path):
    out = tmp_path / "profile.png"
    done = subprocess.run([sys.executable, str(SCRIPTS_DIR / "plot_fibres.py"), str(fibre_results),
                           "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == str(out)
    assert out.read_bytes()[:8] == PNG_MAGIC


def test_script_default_output_and_error(fibre_results, make_results, three_steps, tmp_path):
    done = subprocess.run([sys.executable, str(SCRIPTS_DIR / "plot_fibres.py"), str(fibre_results)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (fibre_results.parent / "helix_angle.png").read_bytes()[:8] == PNG_MAGIC
    other = make_results(three_steps, name="other.h5")
    done = subprocess.run([sys.executable, str(SCRIPTS_DIR / "plot_fibres.py"), str(other)],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert "no helix-angle profile" in done.stderr
