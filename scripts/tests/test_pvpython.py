"""systole_post.pvpython: where the ParaView tests and scripts/run find pvpython
(SYSTOLE_PVPYTHON, then the checkout's .paraview prefix, then PATH), always by an absolute
path."""

import os
import stat
import subprocess
import sys

from systole_post import pvpython


def executable(path):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("#!/bin/sh\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def test_the_variable_then_the_prefix_then_path(tmp_path, monkeypatch):
    root, bin_dir = tmp_path / "checkout", tmp_path / "bin"
    root.mkdir()
    on_path = executable(bin_dir / "pvpython")
    monkeypatch.setenv("PATH", str(bin_dir))
    monkeypatch.delenv("SYSTOLE_PVPYTHON", raising=False)
    assert pvpython.find_pvpython(root) == on_path
    in_prefix = executable(root / ".paraview" / "usr" / "bin" / "pvpython")
    assert pvpython.find_pvpython(root) == in_prefix
    chosen = executable(tmp_path / "elsewhere" / "pvpython")
    monkeypatch.setenv("SYSTOLE_PVPYTHON", str(chosen))
    assert pvpython.find_pvpython(root) == chosen


def test_a_relative_variable_becomes_absolute(tmp_path, monkeypatch):
    # Run through a relative path, the unpacked pvpython imports the system's vtkmodules.
    executable(tmp_path / "pv" / "pvpython")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("SYSTOLE_PVPYTHON", os.path.join("pv", "pvpython"))
    found = pvpython.find_pvpython(tmp_path / "checkout")
    assert found.is_absolute() and found == tmp_path / "pv" / "pvpython"


def test_nothing_found_names_the_fix(tmp_path, monkeypatch):
    root = tmp_path / "checkout"
    executable(root / ".paraview" / "usr" / "bin" / "pvpython")
    (root / ".paraview" / "usr" / "bin" / "pvpython").chmod(0o644)  # not executable
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    monkeypatch.delenv("SYSTOLE_PVPYTHON", raising=False)
    assert pvpython.find_pvpython(root) is None
    assert pvpython.pvpython_command(root) is None
    message = pvpython.missing_message(root)
    assert message.startswith("pvpython and xvfb-run missing")
    assert "systole_install_pvpython" in message
    # A variable pointing nowhere is not silently replaced by the prefix or PATH.
    executable(root / ".paraview" / "usr" / "bin" / "pvpython")
    monkeypatch.setenv("SYSTOLE_PVPYTHON", str(tmp_path / "missing"))
    assert pvpython.find_pvpython(root) is None
    assert "is not an executable" in pvpython.missing_message(root)


def test_command_line_prints_the_path_runs_a_script_or_fails(tmp_path):
    chosen = executable(tmp_path / "pvpython")
    # A stand-in xvfb-run that prints its arguments, one a line.
    xvfb_run = tmp_path / "bin" / "xvfb-run"
    executable(xvfb_run).write_text('#!/bin/sh\nprintf "%s\\n" "$@"\n')
    env = {**os.environ, "SYSTOLE_PVPYTHON": str(chosen),
           "PATH": f"{xvfb_run.parent}{os.pathsep}{os.environ['PATH']}"}

    def run(*args):
        return subprocess.run([sys.executable, "-m", "systole_post.pvpython", *args], env=env,
                              capture_output=True, text=True, check=False)

    done = run("--path")
    assert done.returncode == 0 and done.stdout.strip() == str(chosen)
    done = run("script.py", "a b", "--dump", "x.npz")
    # Xvfb must not reset when pvpython closes its first connection.
    assert done.returncode == 0 and done.stdout.splitlines() == [
        "-a", "-s", "-screen 0 1280x1024x24 -noreset", str(chosen), "script.py", "a b",
        "--dump", "x.npz"]
    env["SYSTOLE_PVPYTHON"] = str(tmp_path / "missing")
    for args in (["--path"], ["script.py"]):
        done = run(*args)
        assert done.returncode == 1 and done.stdout == "" and "SYSTOLE_PVPYTHON" in done.stderr
