"""systole-study: design generation, .prm editing, running and resuming (with a fast fake
runner, tests/fake_systole.py, instead of systole), and the gathered table."""

import csv
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from systole_post import study as st

FAKE = Path(__file__).resolve().parent / "fake_systole.py"
SCRIPTS = Path(__file__).resolve().parent.parent

BASE_PRM = """# A fake problem for the study tests.
set Problem = fake
subsection Fake
  set x1 = 0   # the first input
  set x2 = 0
  set Sleep = {sleep}
  set Fail above = {fail_above}
  set Beats = {beats}
end
"""


def write_study(tmp_path, design, parameters, sleep=0.0, fail_above=1e9, beats=1,
                run="", name="study.toml"):
    (tmp_path / "base.prm").write_text(BASE_PRM.format(sleep=sleep, fail_above=fail_above,
                                                       beats=beats))
    text = f'base = "base.prm"\n[design]\n{design}\n[run]\n{run}\n'
    for pname, body in parameters.items():
        text += f"[parameters.{pname}]\n{body}\n"
    path = tmp_path / name
    path.write_text(text)
    return st.load_study(path)


def fake_command(tmp_path):
    return [sys.executable, str(FAKE), "{prm}", str(tmp_path / "launches.txt")]


def launches(tmp_path):
    path = tmp_path / "launches.txt"
    return path.read_text().split() if path.exists() else []


GRID = {"x1": 'entry = "Fake / x1"\nvalues = [1.0, 2.0, 3.0]',
        "x2": 'entry = "Fake / x2"\nrange = [0.0, 1.0]\nlevels = 2'}
LHS = {"x1": 'entry = "Fake / x1"\nrange = [1.0, 5.0]',
       "x2": 'entry = "Fake / x2"\nrange = [0.01, 100.0]\nlog = true'}


# ------------------------------------------------------------------------------ designs


def test_grid_is_the_full_product_first_parameter_slowest(tmp_path):
    study = write_study(tmp_path, 'type = "grid"', GRID)
    design = st.make_design(study)
    assert [(c["x1"], c["x2"]) for c in design] == [
        (1.0, 0.0), (1.0, 1.0), (2.0, 0.0), (2.0, 1.0), (3.0, 0.0), (3.0, 1.0)]


def test_latin_hypercube_has_one_point_per_stratum_and_depends_only_on_the_seed(tmp_path):
    study = write_study(tmp_path, 'type = "lhs"\nsamples = 16\nseed = 7', LHS)
    design = st.make_design(study)
    x1 = np.array([c["x1"] for c in design])
    log_x2 = np.log10([c["x2"] for c in design])
    assert len(design) == 16
    # One point in each of the 16 equal slices of each (log-)range.
    assert sorted(np.floor((x1 - 1.0) / 4.0 * 16).astype(int)) == list(range(16))
    assert sorted(np.floor((log_x2 + 2.0) / 4.0 * 16).astype(int)) == list(range(16))
    assert st.make_design(study) == design
    other = write_study(tmp_path, 'type = "lhs"\nsamples = 16\nseed = 8', LHS, name="o.toml")
    assert st.make_design(other) != design


def test_sobol_design_fills_the_range_deterministically(tmp_path):
    study = write_study(tmp_path, 'type = "sobol"\nsamples = 32\nseed = 1', LHS)
    design = st.make_design(study)
    x1 = np.array([c["x1"] for c in design])
    assert len(design) == 32 and x1.min() >= 1.0 and x1.max() <= 5.0
    # A scrambled Sobol sequence of 2^5 points has one point in each 1/32 slice.
    assert sorted(np.floor((x1 - 1.0) / 4.0 * 32).astype(int)) == list(range(32))
    assert st.make_design(study) == design
    # Any other size works (without the warning about balance).
    study = write_study(tmp_path, 'type = "sobol"\nsamples = 10', LHS, name="s.toml")
    assert len(st.make_design(study)) == 10


@pytest.mark.parametrize("design, parameters, message", [
    ('type = "lhs"\nsamples = 4', {"x1": 'entry = "Fake / x1"\nvalues = [1, 2]'}, "range"),
    ('type = "grid"', {"x1": 'entry = "Fake / x1"\nrange = [1, 2]'}, "values"),
    ('type = "lhs"', LHS, "samples"),
    ('type = "mesh"', GRID, "design type"),
    ('type = "grid"', {"x1": 'entry = "Fake / x1"\nrange = [2, 1]\nlevels = 2'}, "low < high"),
    ('type = "grid"', {"x1": 'entry = "Fake / / x1"\nvalues = [1]'}, "Section"),
    ('type = "grid"', {"status": 'entry = "Fake / x1"\nvalues = [1]'}, "reserved"),
])
def test_malformed_study_files_are_refused(tmp_path, design, parameters, message):
    with pytest.raises(st.StudyError, match=message):
        write_study(tmp_path, design, parameters)


# ------------------------------------------------------------------------------ .prm editing


def test_set_entries_replaces_appends_and_makes_file_paths_absolute(tmp_path):
    (tmp_path / "mesh.msh").write_text("")
    text = ("set Problem = heartbeat\n"
            "subsection Geometry\n  set Mesh file   = mesh.msh # the mesh\n"
            "  subsection Ellipsoid\n    set Endocardium short radius = 23\n  end\nend\n"
            "subsection Material\n  set a = 1\nend\n")
    out = st.set_entries(text, {("Geometry", "Ellipsoid", "Endocardium  short radius"): 25.5,
                                ("Material", "a"): 2.0,
                                ("Material", "Holzapfel-Ogden", "b"): 3,
                                ("Material", "Holzapfel-Ogden", "a_f"): 0.125,
                                ("Time", "End time"): 800.0}, base_dir=tmp_path)
    assert "    set Endocardium short radius = 25.5\n" in out
    assert "  set a = 2\n" in out
    assert f"set Mesh file   = {(tmp_path / 'mesh.msh').resolve()} # the mesh" in out
    tail = out.split("# Entries set by systole-study\n")[1]
    assert tail == ("subsection Material\n  subsection Holzapfel-Ogden\n    set b = 3\n"
                    "    set a_f = 0.125\n  end\nend\n"
                    "subsection Time\n  set End time = 800\nend\n")
    assert st.parameter_paths(out) >= {("Problem",), ("Material", "Holzapfel-Ogden", "b"),
                                       ("Geometry", "Ellipsoid", "Endocardium short radius")}


# ------------------------------------------------------------------------------ running


def test_study_runs_records_a_failure_and_resumes_only_unfinished_cases(tmp_path):
    # x1 = 3 fails: the study goes on and records the error line.
    study = write_study(tmp_path, 'type = "grid"', GRID, fail_above=2.5)
    out = tmp_path / "out"
    log = open(tmp_path / "progress.txt", "w")  # noqa: SIM115 (closed below)
    counts = st.run_study(study, out, parallel=2, command=fake_command(tmp_path), stream=log)
    assert counts == {"done": 4, "failed": 2, "skipped": 0, "run": 6}
    assert sorted(launches(tmp_path)) == [f"case_{i:04d}" for i in range(6)]
    status = st.read_status(out / "cases" / "case_0004")
    assert status.status == "failed" and status.returncode == 1
    assert status.error == "Error: Newton did not converge at x1 = 3"
    log.flush()
    progress = (tmp_path / "progress.txt").read_text()
    assert "6/6 finished (2 failed)" in progress and "case_0005 failed" in progress

    # Again: nothing to run.
    counts = st.run_study(study, out, command=fake_command(tmp_path), stream=log)
    assert counts == {"done": 0, "failed": 0, "skipped": 6, "run": 0}
    assert len(launches(tmp_path)) == 6

    # A case interrupted midway (no status, a partial results folder) is run again, from
    # scratch; finished cases are not.
    (out / "cases" / "case_0001" / "status.json").unlink()
    (out / "cases" / "case_0001" / "results" / "case" / "results.h5").write_text("partial")
    counts = st.run_study(study, out, command=fake_command(tmp_path), stream=log)
    assert counts == {"done": 1, "failed": 0, "skipped": 5, "run": 1}
    assert launches(tmp_path)[6:] == ["case_0001"]

    # --retry-failed reruns the failed ones only.
    counts = st.run_study(study, out, command=fake_command(tmp_path), stream=log,
                          retry_failed=True)
    assert counts["run"] == 2 and launches(tmp_path)[7:] == ["case_0004", "case_0005"]
    log.close()


def test_a_folder_of_another_study_is_refused(tmp_path):
    study = write_study(tmp_path, 'type = "grid"', GRID)
    st.prepare(study, tmp_path / "out")
    changed = write_study(tmp_path, 'type = "grid"', GRID | {
        "x2": 'entry = "Fake / x2"\nvalues = [5.0]'}, name="changed.toml")
    with pytest.raises(st.StudyError, match="different study"):
        st.prepare(changed, tmp_path / "out")
    # The [run] table may change (more cases at a time on a resumed study).
    same = write_study(tmp_path, 'type = "grid"', GRID, run="parallel = 2", name="same.toml")
    assert len(st.prepare(same, tmp_path / "out")) == 6


def test_a_killed_study_stops_its_cases_and_resumes_without_rerunning_finished_ones(tmp_path):
    write_study(tmp_path, 'type = "lhs"\nsamples = 8\nseed = 3', LHS, sleep=0.4)
    out = tmp_path / "out"
    command = " ".join(fake_command(tmp_path))
    args = [sys.executable, "-m", "systole_post.study", "run", str(tmp_path / "study.toml"),
            "-o", str(out), "--parallel", "2", "--command", command]
    process = subprocess.Popen(args, cwd=SCRIPTS, stdout=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 15
    while len(list(out.glob("cases/*/status.json"))) < 3 and time.monotonic() < deadline:
        time.sleep(0.05)
    process.send_signal(signal.SIGTERM)
    stdout, _ = process.communicate(timeout=30)
    assert process.returncode == 130, stdout
    assert "SIGTERM: stopped" in stdout
    finished = sorted(p.parent.name for p in out.glob("cases/*/status.json"))
    assert 3 <= len(finished) < 8
    first = launches(tmp_path)
    # The table of the stopped study lists every case, finished or pending.
    table = st.read_table(out)
    assert table.n_rows == 8 and table.columns["status"].count("done") == len(finished)

    result = subprocess.run(args, cwd=SCRIPTS, capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    assert f"{len(finished)} finished before" in result.stdout
    second = launches(tmp_path)[len(first):]
    assert not set(second) & set(finished)
    assert sorted(second) == sorted(set(f"case_{i:04d}" for i in range(8)) - set(finished))
    assert st.read_table(out).columns["status"] == ["done"] * 8


# ------------------------------------------------------------------------------ the table


def test_table_gathers_parameters_and_summary_rows_in_csv_and_hdf5(tmp_path):
    study = write_study(tmp_path, 'type = "grid"', GRID, fail_above=2.5, beats=2)
    out = tmp_path / "out"
    with open(tmp_path / "progress.txt", "w") as log:
        st.run_study(study, out, parallel=1, command=fake_command(tmp_path), stream=log)
    with open(out / "table.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert [r["case"] for r in rows] == [f"case_{i:04d}" for i in range(6)]
    assert list(rows[0])[:8] == ["case", "status", "error", "wall_time", "x1", "x2", "beat",
                                "y"]
    # The last beat of each case: y = x1 + 2 x2 + 1; a failed case has empty outputs.
    assert float(rows[3]["y"]) == pytest.approx(2.0 + 2.0 + 1.0)
    assert rows[3]["beat"] == "1.0"
    assert rows[5]["status"] == "failed" and rows[5]["y"] == ""
    assert rows[5]["error"].startswith("Error: Newton")

    table = st.read_table(out)
    assert table.parameter_entries == {"x1": "Fake / x1", "x2": "Fake / x2"}
    assert table.outputs == ["beat", "y", "z_mL"]
    assert table.units["z_mL"] == "mL" and table.ranges == {"x2": (0.0, 1.0)}
    assert np.isnan(table.array("y")[5])
    with h5py.File(out / "table.h5") as h5file:
        assert h5file["table/x1"].attrs["entry"] == "Fake / x1"
        assert list(h5file["table/z_mL"][:4]) == [0.0, 1.0, 0.0, 2.0]

    # summary_rows = "all": one row per case and beat; with events, the beat's valve events.
    study_all = write_study(tmp_path, 'type = "grid"', GRID, fail_above=2.5, beats=2,
                            run='summary_rows = "all"\nevents = true', name="all.toml")
    table = st.gather(out, study_all)
    assert table.columns["case"][:3] == ["case_0000", "case_0000", "case_0001"]
    assert table.n_rows == 4 * 2 + 2
    assert table.columns["valve1_closes_lv_pressure_mmHg"][2:4] == [1.0, 2.0]
    assert table.columns["valve1_opens_time"][3] == 1.5
    assert table.units["valve1_opens_lv_pressure_mmHg"] == "mmHg"


def test_set_table_fixes_entries_of_every_case(tmp_path):
    study = write_study(tmp_path, 'type = "grid"', GRID)
    text = study.path.read_text() + '[set]\n"Fake / Beats" = 3\n"Time / End time" = 1.5\n'
    study.path.write_text(text)
    study = st.load_study(study.path)
    st.prepare(study, tmp_path / "out")
    prm = (tmp_path / "out" / "cases" / "case_0003" / "case.prm").read_text()
    assert "  set Beats = 3\n" in prm and "  set x1 = 2   # the first input\n" in prm and "  set x2 = 1\n" in prm
    assert "subsection Time\n  set End time = 1.5\nend\n" in prm


@pytest.mark.parametrize("recipe", sorted((SCRIPTS.parent / "parameters" / "studies")
                                          .glob("*.toml")), ids=lambda p: p.stem)
def test_every_recipe_loads_and_makes_its_design(recipe, tmp_path):
    study = st.load_study(recipe)
    design = st.make_design(study)
    assert design and study.base.is_file()
    prm = st.case_prm(study, design[0], tmp_path)
    assert st.parameter_paths(prm) >= {p.entry for p in study.parameters} | set(study.fixed)


def test_table_gathers_timeseries_at_the_start_of_each_beat_and_statistics(tmp_path):
    parameters = {"x1": 'entry = "Fake / x1"\nvalues = [3.0]',
                  "x2": 'entry = "Fake / x2"\nvalues = [0.0]'}
    run = ('summary_rows = "all"\ntimeseries_at_start = ["volume", "absent"]\n'
           'statistics = ["n_dofs", "absent"]')
    study = write_study(tmp_path, 'type = "grid"', parameters, beats=2, run=run)
    assert (study.timeseries_at_start, study.statistics) == (["volume", "absent"],
                                                             ["n_dofs", "absent"])
    out = tmp_path / "out"
    with open(tmp_path / "progress.txt", "w") as log:
        st.run_study(study, out, command=fake_command(tmp_path), stream=log)
    # The fake's volume goes from 1 to x1 = 3 over t = 0 ... 1; let its beats start at 0 and
    # 0.5 and give it a /statistics group.
    with h5py.File(out / "cases" / "case_0000" / st.RESULTS_IN_CASE, "a") as h5file:
        h5file["summary"].create_dataset("start_time", data=[0.0, 0.5])
        h5file.create_group("statistics").create_dataset("n_dofs", data=801.0)
    table = st.gather(out, study)
    assert table.columns["start_volume"] == [1.0, 2.0]
    assert table.units["start_volume"] == "mm^3"
    assert table.columns["statistics_n_dofs"] == [801.0, 801.0]
    assert "start_absent" not in table.columns and "statistics_absent" not in table.columns
