#!/usr/bin/env python3
"""Checkpoint and restart of the heartbeat: killed runs resume and lose nothing.

    checkpoint_resume.py MODE SYSTOLE MPIEXEC PRM [KILL_STEP [REFERENCE.h5]]

PRM writes a checkpoint every 20 steps. Every mode works in the current folder, on run names of
its own (an Output subsection appended to a copy of PRM; only Output may differ on resume):

- reference: the uninterrupted run (1 rank), results/reference.
- chain: killed with SIGKILL after step 22, resumed (Output / Resume = true, from step 20) and
  killed halfway through writing the checkpoint of step 60, resumed (from step 40: the
  unfinished checkpoint.tmp is never read) and killed after step 82, resumed to the end (from
  step 80); /timeseries, /events and /summary equal the reference to 1e-12 (relative to each
  column's largest value; the wall-time columns *_seconds excepted). The kills come two steps
  after a checkpoint: each resume repeats two steps.
- ranks-2-1 / ranks-1-2 / ranks-2-3: killed on 2 ranks after step 25 and resumed on 1, or
  killed on 1 rank (2 ranks) after step 105 and resumed on 2 (3 ranks); equal to the reference
  to 1e-8 (the *_drift columns, round-off by definition, to 1e-10 absolute besides; every
  column to 1e-13 absolute besides, for coordinates that are zero by symmetry).
  KILL_STEP replaces the step of the kill ('-': the mode's own), REFERENCE.h5 the reference
  run (e.g. a run test of PRM itself; for chain too, whose reference folder must then hold
  the last two checkpoints as the reference mode's).
- other-build (by hand: docs/verification.md): like ranks-2-3, but resumed by OTHER_SYSTOLE, the
  app of another build (e.g. CMAKE_BUILD_TYPE=Debug) of the same checkpoint format:

      checkpoint_resume.py other-build SYSTOLE MPIEXEC PRM KILL_STEP REFERENCE.h5 OTHER_SYSTOLE

- reference-2 / ranks-2-2: the uninterrupted run on 2 ranks (results/reference_2); killed on 2
  ranks after step 45 (or KILL_STEP) and resumed on 2: equal to reference-2 to 1e-12 (a
  tetrahedral mesh resumes on the rank count it was saved with, in the saved partition).
- ranks-2-1-refused: a copy of the ranks-2-2 run resumed on 1 rank fails with one line
  naming both rank counts (a fully distributed mesh cannot be repartitioned on load).
- corrupt: a copy of the reference run with the newest checkpoint's state.txt truncated;
  resuming (systole --resume) prints one line naming that file and falls back to the
  previous checkpoint; the results equal the reference to 1e-12.
- wrong-format: a copy of the reference run whose newest checkpoint says format 99 in the
  header of its state.txt (the manifest updated, so it is a valid checkpoint of another
  format), then one whose newest checkpoint has the binary state.bin of format 1: resuming
  fails with one line naming both format versions.
- wrong-parameters: resuming a copy of the reference run with a parameter file of another
  mesh (Geometry / Global refinements = 1) fails with a message naming that entry.

The kills use the test-only entries Output / Test kill after step (SIGKILL after a step) and
Output / Test kill in checkpoint (SIGKILL while writing that step's checkpoint).
"""

import re
import shutil
import subprocess
import sys
from pathlib import Path

import zlib

import h5py
import numpy as np

GROUPS = ("timeseries", "events", "summary")


def prm_for(prm: Path, run: str, extra: str = "", file: str = "") -> Path:
    out = Path(f"{file or run}.prm")
    # A mesh file named relative to PRM's folder, named from here.
    text = re.sub(r"(set Mesh file\s*=\s*)(\S+)",
                  lambda m: m.group(1) + str((prm.parent / m.group(2)).resolve()),
                  prm.read_text())
    out.write_text(text + f"\nsubsection Output\n  set Run name = {run}\n{extra}end\n")
    return out


def kill_after(step) -> str:
    return f"  set Test kill after step = {step}\n"


RESUME = "  set Resume = true\n"


def run(cmd, expect_kill=False, expect_fail=False):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    log = p.stdout + p.stderr
    if expect_kill:
        # SIGKILL: -9 directly, 137 through mpirun.
        if p.returncode not in (-9, 137):
            sys.exit(f"expected a kill, got exit code {p.returncode}:\n{log[-3000:]}")
    elif expect_fail:
        if p.returncode == 0:
            sys.exit(f"expected a failure:\n{log[-3000:]}")
    elif p.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({p.returncode}):\n{log[-3000:]}")
    return log


#: Columns that depend on the partition (compared only on the same rank count): Krylov
#: iteration counts, and the Newton and chord counts and residuals that round-off can tip.
PARTITION_DEPENDENT = ("linear_iterations", "newton_iterations", "chord_iterations", "residual")


def compare(reference: Path, result: Path, tolerance: float, floor: float = 0.0,
            other_ranks: bool = False) -> None:
    with h5py.File(reference, "r") as a, h5py.File(result, "r") as b:
        worst = (0.0, "")
        for group in GROUPS:
            if group not in a and group not in b:
                continue  # (Problem = electrophysiology has no /events)
            names_a, names_b = list(a[group]), list(b[group])
            if names_a != names_b:
                sys.exit(f"/{group}: columns differ: {names_a} vs {names_b}")
            for name in names_a:
                if name.endswith("_seconds"):
                    continue  # wall times
                if other_ranks and name in PARTITION_DEPENDENT:
                    continue
                x, y = a[group][name][()], b[group][name][()]
                if x.shape != y.shape:
                    sys.exit(f"/{group}/{name}: {x.shape[0]} rows, resumed {y.shape[0]}")
                both_nan = np.isnan(x) & np.isnan(y)
                if np.any(np.isnan(x) != np.isnan(y)):
                    sys.exit(f"/{group}/{name}: NaN in one run only")
                scale = max(np.max(np.abs(np.where(both_nan, 0, x))), 1e-300)
                d = np.max(np.abs(np.where(both_nan, 0, x - y))) / scale if x.size else 0.0
                if d > worst[0]:
                    worst = (d, f"/{group}/{name}")
                # (floor: an absolute allowance for the drift columns, round-off by
                # definition: the relative blood-volume drift of a closed loop, ~1e-15.)
                # (On another rank count also 1e-13 absolute: a coordinate that is zero
                # by symmetry, e.g. a point on the axis, holds round-off, ~1e-16 mm.)
                allowed = tolerance * scale + (floor if name.endswith("_drift") else 0.0) \
                    + (1e-13 if other_ranks else 0.0)
                if not d * scale <= allowed:
                    sys.exit(f"/{group}/{name}: resumed differs by {d:.3e} (relative to the "
                             f"column's largest value) > {tolerance:g}")
        rows = {g: a[g][list(a[g])[0]].shape[0] for g in GROUPS if g in a}
    print(f"{result}: equal to {reference} within {tolerance:g} ({rows}); largest "
          f"difference {worst[0]:.3e} {worst[1]}")


def last_two_checkpoints_kept(run_folder: Path) -> None:
    checkpoints = sorted(run_folder.glob("checkpoint_*"))
    assert len(checkpoints) == 2, f"the last two checkpoints kept, found {checkpoints}"


def main() -> None:
    mode, systole, mpiexec, prm = sys.argv[1], Path(sys.argv[2]), sys.argv[3], Path(sys.argv[4])
    mpi2 = [mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", "2", systole]
    mpi3 = [mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", "3", systole]
    kill_step = sys.argv[5] if len(sys.argv) > 5 and sys.argv[5] != "-" else None
    reference = Path(sys.argv[6] if len(sys.argv) > 6 else "results/reference/results.h5")

    if mode == "reference":
        shutil.rmtree("results/reference", ignore_errors=True)
        run([systole, prm_for(prm, "reference")])
        last_two_checkpoints_kept(Path("results/reference"))
        return

    if mode == "chain":
        shutil.rmtree("results/chain", ignore_errors=True)
        if len(sys.argv) > 6:
            last_two_checkpoints_kept(reference.parent)
        # The kills are test-only entries of subsection Output (which may differ on a resume),
        # so every run here names its own file (systole --resume would read the file the run
        # was started with, its kill included).
        run([systole, prm_for(prm, "chain", kill_after(22), "chain_kill22")], expect_kill=True)
        log = run([systole, prm_for(prm, "chain", RESUME + "  set Test kill in checkpoint = 60\n",
                                    "chain_kill60")], expect_kill=True)
        assert "Resuming from results/chain/checkpoint_000020" in log, log[-2000:]
        assert Path("results/chain/checkpoint.tmp").is_dir(), "no unfinished checkpoint left"
        log = run([systole, prm_for(prm, "chain", RESUME + kill_after(82), "chain_kill82")],
                  expect_kill=True)
        assert "Resuming from results/chain/checkpoint_000040" in log, log[-2000:]
        log = run([systole, prm_for(prm, "chain", RESUME, "chain_resume")])
        assert "Resuming from results/chain/checkpoint_000080" in log, log[-2000:]
        compare(reference, Path("results/chain/results.h5"), 1e-12)
        return

    if mode in ("ranks-2-1", "ranks-1-2", "ranks-2-3"):
        name = mode.replace("-", "_")
        shutil.rmtree(f"results/{name}", ignore_errors=True)
        first, then, step = {"ranks-2-1": (mpi2, [systole], "25"),
                             "ranks-1-2": ([systole], mpi2, "105"),
                             "ranks-2-3": (mpi2, mpi3, "105")}[mode]
        step = kill_step or step
        run(first + [prm_for(prm, name, kill_after(step), name + "_kill")], expect_kill=True)
        log = run(then + [prm_for(prm, name, RESUME, name + "_resume")])
        assert "Resuming from" in log, log[-2000:]
        # Another rank count: 1e-8 relative, the drift columns 1e-10 absolute besides.
        compare(reference, Path(f"results/{name}/results.h5"), 1e-8, 1e-10, other_ranks=True)
        return

    if mode == "other-build":
        other = Path(sys.argv[7])
        mpi3_other = mpi3[:-1] + [other]
        shutil.rmtree("results/other_build", ignore_errors=True)
        run(mpi2 + [prm_for(prm, "other_build", kill_after(kill_step), "other_build_kill")],
            expect_kill=True)
        log = run(mpi3_other + [prm_for(prm, "other_build", RESUME, "other_build_resume")])
        assert "Resuming from" in log, log[-2000:]
        print(next(line for line in log.splitlines() if "Resuming from" in line))
        compare(reference, Path("results/other_build/results.h5"), 1e-8, 1e-10,
                other_ranks=True)
        return

    if mode == "reference-2":
        shutil.rmtree("results/reference_2", ignore_errors=True)
        run(mpi2 + [prm_for(prm, "reference_2")])
        return

    if mode == "ranks-2-2":
        shutil.rmtree("results/ranks_2_2", ignore_errors=True)
        run(mpi2 + [prm_for(prm, "ranks_2_2", kill_after(kill_step or 45), "ranks_2_2_kill")],
            expect_kill=True)
        log = run(mpi2 + [prm_for(prm, "ranks_2_2", RESUME, "ranks_2_2_resume")])
        assert "Resuming from" in log, log[-2000:]
        compare(Path("results/reference_2/results.h5"), Path("results/ranks_2_2/results.h5"),
                1e-12)
        return

    if mode == "ranks-2-1-refused":
        shutil.rmtree("results/refused", ignore_errors=True)
        shutil.copytree("results/ranks_2_2", "results/refused")
        log = run([systole, "--resume", "results/refused"], expect_fail=True)
        lines = [line for line in log.splitlines() if "error" in line]
        expected = "was written on 2 rank(s) and cannot resume on 1"
        assert len(lines) == 1 and expected in lines[0], \
            f"expected one line '... {expected} ...':\n{log[-2000:]}"
        print(lines[0])
        return

    if mode == "corrupt":
        shutil.rmtree("results/corrupt", ignore_errors=True)
        shutil.copytree("results/reference", "results/corrupt")
        checkpoints = sorted(Path("results/corrupt").glob("checkpoint_*"))
        state = checkpoints[-1] / "state.txt"
        data = state.read_bytes()
        state.write_bytes(data[: len(data) // 2])
        # systole --resume: the parameter file the run was started with (reference's).
        log = run([systole, "--resume", "results/corrupt"])
        lines = [line for line in log.splitlines() if "Checkpoint fault" in line]
        expected = f"{state} is truncated or corrupt"
        assert len(lines) == 1 and expected in lines[0] and \
            f"falling back to {checkpoints[-2]}" in lines[0], \
            f"expected one line '{expected} ... falling back to {checkpoints[-2]}':\n{log[-2000:]}"
        assert f"Resuming from {checkpoints[-2]}" in log, log[-2000:]
        print(lines[0])
        compare(reference, Path("results/corrupt/results.h5"), 1e-12)
        return

    if mode == "wrong-format":
        for case, expected in (("newer", "is in checkpoint format 99 (written by systole"),
                               ("old", "is in checkpoint format 1 (a binary state.bin")):
            run_dir = Path(f"results/format_{case}")
            shutil.rmtree(run_dir, ignore_errors=True)
            shutil.copytree("results/reference", run_dir)
            newest = sorted(run_dir.glob("checkpoint_*"))[-1]
            state = newest / "state.txt"
            if case == "newer":
                text = state.read_text()
                head, rest = text.split("\n", 1)
                words = head.split(" ")
                assert words[0] == "systole-checkpoint", head
                words[1] = "99"
                state.write_text(" ".join(words) + "\n" + rest)
            else:
                state.rename(newest / "state.bin")
            # A valid checkpoint of that format: the manifest (size, CRC-32, name) rewritten.
            lines = []
            for line in (newest / "MANIFEST").read_text().splitlines():
                name = line.split(" ")[2]
                if name == "state.txt":
                    name = "state.bin" if case == "old" else name
                data = (newest / name).read_bytes()
                lines.append(f"{len(data)} {zlib.crc32(data):x} {name}")
            (newest / "MANIFEST").write_text("\n".join(lines) + "\n")
            log = run([systole, "--resume", str(run_dir)], expect_fail=True)
            errors = [line for line in log.splitlines() if "format" in line]
            current = (Path("results/reference") / newest.name / "state.txt").read_text() \
                .split(" ")[1]
            both = f"reads format {current}"
            assert len(errors) == 1 and expected in errors[0] and both in errors[0], \
                f"expected one line '{expected} ... {both}':\n{log[-2000:]}"
            print(errors[0])
        return

    if mode == "wrong-parameters":
        shutil.rmtree("results/wrong", ignore_errors=True)
        shutil.copytree("results/reference", "results/wrong")
        text = prm.read_text().replace("subsection Geometry\n",
                                       "subsection Geometry\n  set Global refinements = 1\n", 1)
        other = Path("other_mesh.prm")
        other.write_text(text)
        log = run([systole, prm_for(other, "wrong", "  set Resume = true\n")], expect_fail=True)
        expected = "Geometry / Global refinements: '0' in the checkpoint, '1' now"
        assert expected in log and "was written for another problem" in log, \
            f"expected '{expected}':\n{log[-2000:]}"
        print(log.strip().splitlines()[-1])
        return

    sys.exit(f"unknown mode {mode}")


if __name__ == "__main__":
    main()
