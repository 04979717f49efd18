"""Parameter studies: many runs of one base .prm, N at a time, resumable, gathered into a table.

A study file (TOML) names the base parameter file, the entries to vary and the design::

    base = "../../tests/runs/lv_heartbeat_coarse.prm"   # relative to the study file

    [design]
    type = "lhs"          # grid | lhs | sobol
    samples = 16          # lhs, sobol
    seed = 1              # lhs, sobol (scrambling)

    [run]                 # defaults of the command-line options
    parallel = 2          # cases at a time
    ranks = 1             # MPI ranks per case
    summary_rows = "last" # "last": one row per case (its last beat); "all": every beat
    timeseries_final = [] # /timeseries columns whose last value joins the table (final_<name>)
    timeseries_at_start = []  # /timeseries columns at the start of the row's beat (start_<name>)
    statistics = []       # /statistics values of the run (statistics_<name>), e.g. n_dofs
    events = false        # true: the beat's valve events join the table, e.g.
                          # valve1_closes_lv_pressure_mmHg (valve numbers as in /events)

    [set]                 # entries set in every case (the same for all)
    "Postprocess / List of postprocessors" = "ventricle function"

    [parameters.stiffness]               # column name in the table
    entry = "Material / Holzapfel-Ogden / a"
    range = [1.5, 3.0]                   # lhs, sobol: sampled uniformly in [low, high]
    log = false                          # true: uniformly in log(value)
    # values = [1.5, 2.0, 2.5]           # grid: these values ...
    # levels = 4                         # ... or this many evenly spaced points of range

A grid is the full product of the parameters' values (the first parameter varies slowest).
Each case is a folder ``cases/case_NNNN`` of the output folder holding ``case.prm`` (the base
file with the case's entries set; relative file paths made absolute), ``stdout.txt``,
``stderr.txt``, ``results/case/results.h5`` and, once it has finished, ``status.json``
(status done or failed, exit code, error line, wall time). Running the study again skips
every case with a status (``--retry-failed`` reruns the failed ones) and reruns those that
were interrupted. ``study.json`` keeps the design; a changed study or base file is refused.

The table (``table.csv``, ``table.h5``) has one row per case (or per case and beat):
``case``, ``status``, ``error``, ``wall_time``, the parameters, and the /summary columns.

Command line::

    systole-study run STUDY.toml [-o DIR] [--parallel N] [--ranks R] [--retry-failed]
    systole-study table DIR
    systole-study sensitivity DIR --output lv_EF [--output ...]
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import itertools
import json
import math
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time
import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from systole_post.results import ResultsError, read_results

#: Where a case's run writes its results, relative to the case folder (the study sets
#: Output / Directory and Output / Run name to match).
RESULTS_IN_CASE = Path("results") / "case" / "results.h5"

#: Columns every table starts with, before the parameters and the outputs.
LEADING_COLUMNS = ("case", "status", "error", "wall_time")

DESIGN_TYPES = ("grid", "lhs", "sobol")


class StudyError(Exception):
    """A malformed study file, a study folder of another study, or a base file problem."""


@dataclass(frozen=True)
class Parameter:
    """One varied entry of the base parameter file.

    Attributes:
        name: column name in the table (the key of its [parameters.NAME] table).
        entry: the path of the entry: subsections, then the entry name.
        low, high: the range (lhs, sobol; grid with levels), else None.
        values: explicit grid values, else None.
        levels: number of evenly spaced grid points of the range, else None.
        log: sample (or space the levels) uniformly in log(value).
    """

    name: str
    entry: tuple[str, ...]
    low: float | None = None
    high: float | None = None
    values: tuple | None = None
    levels: int | None = None
    log: bool = False

    @property
    def entry_text(self) -> str:
        return " / ".join(self.entry)

    def scale(self, unit: np.ndarray) -> np.ndarray:
        """Map points of [0, 1] to the range (in log space when ``log``)."""
        if self.log:
            return np.exp(np.log(self.low) + unit * (np.log(self.high) - np.log(self.low)))
        return self.low + unit * (self.high - self.low)

    def grid_values(self) -> list:
        if self.values is not None:
            return list(self.values)
        return list(self.scale(np.linspace(0.0, 1.0, self.levels)))


@dataclass
class Study:
    """A parsed study file.

    Attributes:
        path: the study file.
        base: the base parameter file (absolute).
        parameters: the varied entries, in file order.
        design: the [design] table (type, samples, seed, ...).
        parallel, ranks: cases at a time and MPI ranks per case.
        summary_rows: "last" or "all".
        timeseries_final: /timeseries columns whose last value is gathered.
        timeseries_at_start: /timeseries columns gathered at the start of the row's beat.
        statistics: /statistics values gathered (the same in every row of a case).
        text: the study file's text; base_text: the base file's text.
    """

    path: Path
    base: Path
    parameters: list[Parameter]
    design: dict
    parallel: int = 1
    ranks: int = 1
    summary_rows: str = "last"
    timeseries_final: list[str] = field(default_factory=list)
    timeseries_at_start: list[str] = field(default_factory=list)
    statistics: list[str] = field(default_factory=list)
    events: bool = False
    fixed: dict = field(default_factory=dict)
    text: str = ""
    base_text: str = ""

    def fingerprint(self) -> str:
        """Hash of what defines the cases (design, parameters, base file), not of [run]."""
        key = json.dumps({"design": self.design,
                          "parameters": [p.__dict__ | {"entry": list(p.entry)}
                                         for p in self.parameters],
                          "set": {" / ".join(k): v for k, v in self.fixed.items()},
                          "base": self.base_text}, sort_keys=True, default=str)
        return hashlib.sha256(key.encode()).hexdigest()[:16]


def split_entry(text: str) -> tuple[str, ...]:
    """``"Material / Holzapfel-Ogden / a"`` -> ("Material", "Holzapfel-Ogden", "a")."""
    parts = tuple(" ".join(part.split()) for part in text.split("/"))
    if not parts or any(not part for part in parts):
        raise StudyError(f"entry '{text}' is not of the form 'Section / ... / Entry'")
    return parts


def _parameter(name: str, table: dict, design_type: str) -> Parameter:
    if "entry" not in table:
        raise StudyError(f"parameter '{name}' has no entry")
    unknown = set(table) - {"entry", "range", "values", "levels", "log"}
    if unknown:
        raise StudyError(f"parameter '{name}': unknown key(s) {sorted(unknown)}")
    low = high = None
    if "range" in table:
        rng = table["range"]
        if (not isinstance(rng, list) or len(rng) != 2
                or not all(isinstance(v, (int, float)) for v in rng) or not rng[0] < rng[1]):
            raise StudyError(f"parameter '{name}': range must be [low, high] with low < high")
        low, high = float(rng[0]), float(rng[1])
    log = bool(table.get("log", False))
    if log and low is not None and low <= 0:
        raise StudyError(f"parameter '{name}': a log range must be positive")
    values = tuple(table["values"]) if "values" in table else None
    levels = table.get("levels")
    if design_type == "grid":
        if values is None and (levels is None or low is None):
            raise StudyError(f"parameter '{name}': a grid needs values, or range and levels")
        if values is not None and not values:
            raise StudyError(f"parameter '{name}': values is empty")
        if levels is not None and (not isinstance(levels, int) or levels < 1):
            raise StudyError(f"parameter '{name}': levels must be a positive integer")
    elif low is None:
        raise StudyError(f"parameter '{name}': a {design_type} design needs a range")
    return Parameter(name, split_entry(table["entry"]), low, high, values, levels, log)


def load_study(path: str | Path) -> Study:
    """Read and check a study file (see the module documentation)."""
    path = Path(path).resolve()
    text = path.read_text()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise StudyError(f"{path}: {error}") from None
    unknown = set(data) - {"base", "design", "run", "parameters", "set", "description"}
    if unknown:
        raise StudyError(f"{path}: unknown key(s) {sorted(unknown)}")
    if "base" not in data:
        raise StudyError(f"{path}: no base parameter file (base = \"...\")")
    base = (path.parent / data["base"]).resolve()
    if not base.is_file():
        raise StudyError(f"{path}: base file {base} does not exist")
    design = dict(data.get("design", {}))
    design_type = design.setdefault("type", "grid")
    if design_type not in DESIGN_TYPES:
        raise StudyError(f"{path}: design type '{design_type}' is not one of {DESIGN_TYPES}")
    if design_type != "grid":
        samples = design.get("samples")
        if not isinstance(samples, int) or samples < 1:
            raise StudyError(f"{path}: a {design_type} design needs samples (a positive integer)")
        design.setdefault("seed", 0)
    tables = data.get("parameters", {})
    if not tables:
        raise StudyError(f"{path}: no [parameters.NAME] tables")
    parameters = [_parameter(name, table, design_type) for name, table in tables.items()]
    clash = {p.name for p in parameters} & set(LEADING_COLUMNS)
    if clash:
        raise StudyError(f"{path}: parameter name(s) {sorted(clash)} are reserved")
    run = data.get("run", {})
    unknown = set(run) - {"parallel", "ranks", "summary_rows", "timeseries_final",
                          "timeseries_at_start", "statistics", "events"}
    if unknown:
        raise StudyError(f"{path}: unknown [run] key(s) {sorted(unknown)}")
    summary_rows = run.get("summary_rows", "last")
    if summary_rows not in ("last", "all"):
        raise StudyError(f"{path}: summary_rows must be 'last' or 'all'")
    return Study(path=path, base=base, parameters=parameters, design=design,
                 parallel=int(run.get("parallel", 1)), ranks=int(run.get("ranks", 1)),
                 summary_rows=summary_rows,
                 timeseries_final=list(run.get("timeseries_final", [])),
                 timeseries_at_start=list(run.get("timeseries_at_start", [])),
                 statistics=list(run.get("statistics", [])),
                 events=bool(run.get("events", False)),
                 fixed={split_entry(k): v for k, v in data.get("set", {}).items()},
                 text=text, base_text=base.read_text())


def make_design(study: Study) -> list[dict]:
    """The cases of the study: one dict parameter name -> value per case, in case order."""
    design_type = study.design["type"]
    params = study.parameters
    if design_type == "grid":
        product = itertools.product(*(p.grid_values() for p in params))
        return [dict(zip((p.name for p in params), values)) for values in product]
    from scipy.stats import qmc

    n, d, seed = study.design["samples"], len(params), study.design["seed"]
    if design_type == "lhs":
        # random-cd spreads the points (lower discrepancy), which helps an emulator;
        # deterministic for a given seed.
        optimization = study.design.get("optimization", "random-cd" if d > 1 else None)
        unit = qmc.LatinHypercube(d, seed=seed, optimization=optimization).random(n)
    else:
        sampler = qmc.Sobol(d, scramble=True, seed=seed)
        with warnings.catch_warnings():
            # Balance properties need a power of 2; other sizes still work.
            warnings.simplefilter("ignore", UserWarning)
            unit = sampler.random(n)
    columns = [p.scale(unit[:, j]) for j, p in enumerate(params)]
    return [{p.name: float(columns[j][i]) for j, p in enumerate(params)} for i in range(n)]


# ----------------------------------------------------------------------------- prm editing

_SUBSECTION = re.compile(r"^\s*subsection\s+(.*?)\s*$")
_END = re.compile(r"^\s*end\s*$")
_SET = re.compile(r"^(\s*set\s+)(.*?)(\s*=\s*)(.*?)(\s*(#.*)?)$")
_INCLUDE = re.compile(r"^(\s*include\s+)(\S.*?)\s*$")


def format_value(value) -> str:
    """A parameter value as .prm text (floats to 12 significant digits)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.12g}"
    return str(value)


def _walk(prm_text: str):
    """Yield (line, entry path or None, the `set` match or None) for every line of a .prm
    text, tracking its subsections."""
    stack: list[str] = []
    for line in prm_text.splitlines():
        if m := _SUBSECTION.match(line):
            stack.append(" ".join(m.group(1).split()))
        elif _END.match(line) and stack:
            stack.pop()
        elif m := _SET.match(line):
            yield line, tuple(stack) + (" ".join(m.group(2).split()),), m
            continue
        yield line, None, None


def _looks_like_file(value: str) -> bool:
    return bool(re.fullmatch(r"[\w.+-]+(/[\w.+-]+)*\.\w+", value))


def set_entries(prm_text: str, entries: dict[tuple[str, ...], object],
                base_dir: Path | None = None, include_dir: Path | None = None) -> str:
    """Return ``prm_text`` with the given entries set.

    An entry set in the text gets its value replaced (every occurrence, in its subsection);
    one that is not is appended at the end in its subsections. With ``base_dir``, a value
    that names an existing file relative to it becomes an absolute path (Systole resolves
    file entries relative to the parameter file's folder, and the case file lives
    elsewhere); with ``include_dir``, so does a relative ``include`` (deal.II resolves it
    relative to the working folder).
    """
    norm = {tuple(" ".join(p.split()) for p in key): value for key, value in entries.items()}
    found = set()
    out = []
    for line, key, m in _walk(prm_text):
        if key is not None:
            if key in norm:
                found.add(key)
                line = (m.group(1) + m.group(2) + m.group(3) + format_value(norm[key])
                        + m.group(5))
            elif base_dir is not None:
                value = m.group(4)
                if _looks_like_file(value) and (base_dir / value).is_file():
                    line = (m.group(1) + m.group(2) + m.group(3)
                            + str((base_dir / value).resolve()) + m.group(5))
        elif include_dir is not None and (m := _INCLUDE.match(line)):
            target = Path(m.group(2))
            if not target.is_absolute():
                line = m.group(1) + str((include_dir / target).resolve())
        out.append(line)
    missing = [key for key in norm if key not in found]
    if missing:
        out.append("")
        out.append("# Entries set by systole-study")
        _append_tree(out, {key: format_value(norm[key]) for key in missing}, 0)
    return "\n".join(out) + "\n"


def _append_tree(out: list[str], entries: dict[tuple[str, ...], str], depth: int) -> None:
    """Append ``set`` lines for entries (paths relative to the current depth), grouped into
    one block per subsection, in first-appearance order."""
    groups: dict[str, dict] = {}
    for key, value in entries.items():
        if len(key) == 1:
            out.append("  " * depth + f"set {key[0]} = {value}")
        else:
            groups.setdefault(key[0], {})[key[1:]] = value
    for name, sub in groups.items():
        out.append("  " * depth + f"subsection {name}")
        _append_tree(out, sub, depth + 1)
        out.append("  " * depth + "end")


def case_prm(study: Study, values: dict, include_dir: Path) -> str:
    """The parameter file of one case: the base with its values and the study's output."""
    entries = dict(study.fixed)
    entries.update({p.entry: values[p.name] for p in study.parameters})
    entries[("Output", "Directory")] = RESULTS_IN_CASE.parts[0]
    entries[("Output", "Run name")] = RESULTS_IN_CASE.parts[1]
    header = "# Written by systole-study from " + study.base.name + ": " + ", ".join(
        f"{p.entry_text} = {format_value(values[p.name])}" for p in study.parameters)
    return header + "\n" + set_entries(study.base_text, entries, study.base.parent, include_dir)


def parameter_paths(prm_text: str) -> set[tuple[str, ...]]:
    """Every entry path of a .prm text (e.g. the output of ``systole --print-parameters``)."""
    return {key for _, key, _ in _walk(prm_text) if key is not None}


# ----------------------------------------------------------------------------- running


@dataclass
class CaseOutcome:
    """What status.json of a finished case holds."""

    status: str  # "done" or "failed"
    returncode: int
    error: str
    wall_time: float


def case_name(index: int) -> str:
    return f"case_{index:04d}"


def read_status(case_dir: Path) -> CaseOutcome | None:
    """The outcome of a finished case, or None if it has not finished."""
    try:
        data = json.loads((case_dir / "status.json").read_text())
        return CaseOutcome(**data)
    except (FileNotFoundError, json.JSONDecodeError, TypeError):
        return None


def write_status(case_dir: Path, outcome: CaseOutcome) -> None:
    """Write status.json atomically (a study killed while writing leaves no half file)."""
    tmp = case_dir / "status.json.tmp"
    tmp.write_text(json.dumps(outcome.__dict__, indent=1) + "\n")
    os.replace(tmp, case_dir / "status.json")


def error_line(stderr: str, stdout: str, returncode: int) -> str:
    """The line that says why a run failed: the last non-empty line of stderr, else stdout."""
    for text in (stderr, stdout):
        lines = [line.strip() for line in text.splitlines() if line.strip()]
        if lines:
            return lines[-1]
    return f"exited with status {returncode} and no output"


def default_command(ranks: int, systole: str) -> list[str]:
    """How scripts/run starts Systole; one rank runs without mpirun (as the ctest runs do)."""
    if ranks == 1:
        return [systole, "{prm}"]
    return ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), systole,
            "{prm}"]


def find_systole() -> str:
    """$SYSTOLE_BUILD/systole, else build/systole of the repository holding this package."""
    build = os.environ.get("SYSTOLE_BUILD")
    if build:
        return str(Path(build) / "systole")
    return str(Path(__file__).resolve().parents[2] / "build" / "systole")


class _Running:
    def __init__(self, index, case_dir, process, stdout, stderr):
        self.index = index
        self.case_dir = case_dir
        self.process = process
        self.stdout = stdout
        self.stderr = stderr
        self.start = time.monotonic()


def _format_seconds(seconds: float) -> str:
    seconds = int(round(seconds))
    if seconds >= 3600:
        return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"
    if seconds >= 60:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds}s"


class Progress:
    """done / running / failed and the time left, one line (rewritten on a terminal)."""

    def __init__(self, n_cases, parallel, stream=None):
        self.n_cases = n_cases
        self.parallel = parallel
        self.stream = stream if stream is not None else sys.stdout
        self.tty = self.stream.isatty()
        self.start = time.monotonic()
        self.durations: list[float] = []
        self.last = ""

    def line(self, done, failed, running: list[_Running], pending) -> str:
        now = time.monotonic()
        text = (f"[study] {done + failed}/{self.n_cases} finished ({failed} failed), "
                f"{len(running)} running, {pending} pending; "
                f"elapsed {_format_seconds(now - self.start)}")
        if self.durations and (running or pending):
            mean = sum(self.durations) / len(self.durations)
            busy = sum(max(mean - (now - r.start), 0.0) for r in running) + pending * mean
            text += f", left ~{_format_seconds(busy / max(1, min(self.parallel, len(running) + pending)))}"
        return text

    def show(self, text, event=None):
        if self.tty:
            if event:
                self.stream.write("\r\033[K" + event + "\n")
            self.stream.write("\r\033[K" + text)
        elif event:
            self.stream.write(event + "  | " + text + "\n")
        self.stream.flush()
        self.last = text

    def finish(self):
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()


class Interrupted(Exception):
    """The study received SIGTERM or SIGINT; its running cases were stopped."""


def _stop(process: subprocess.Popen, grace: float = 20.0) -> None:
    """Stop a case's process group: SIGTERM (Systole writes a checkpoint), then SIGKILL."""
    try:
        os.killpg(process.pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    try:
        process.wait(timeout=grace)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        process.wait()


def prepare(study: Study, out_dir: Path, include_dir: Path | None = None) -> list[dict]:
    """Create (or check) the study folder and every case folder; return the design.

    A folder of an earlier run of the same study keeps its design (so a resumed study runs
    the same cases); a folder of a different study (other design, parameters or base
    file) is refused.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    meta_path = out_dir / "study.json"
    design = make_design(study)
    if meta_path.exists():
        meta = json.loads(meta_path.read_text())
        if meta.get("fingerprint") != study.fingerprint():
            raise StudyError(f"{out_dir} holds a different study (its design, parameters or "
                             "base file changed); use another output folder")
        design = meta["design"]
    else:
        meta = {"fingerprint": study.fingerprint(), "study_file": study.path.name,
                "base": str(study.base), "study": study.text,
                "parameters": [{"name": p.name, "entry": p.entry_text, "low": p.low,
                                "high": p.high, "log": p.log} for p in study.parameters],
                "design": design}
        tmp = out_dir / "study.json.tmp"
        tmp.write_text(json.dumps(meta, indent=1) + "\n")
        os.replace(tmp, meta_path)
    include_dir = include_dir or Path.cwd()
    for index, values in enumerate(design):
        case_dir = out_dir / "cases" / case_name(index)
        case_dir.mkdir(parents=True, exist_ok=True)
        prm = case_prm(study, values, include_dir)
        prm_path = case_dir / "case.prm"
        if not prm_path.exists() or prm_path.read_text() != prm:
            prm_path.write_text(prm)
    return design


def _check_outcome(case_dir: Path, returncode: int, wall_time: float,
                   study: Study) -> CaseOutcome:
    stdout = (case_dir / "stdout.txt").read_text(errors="replace")
    stderr = (case_dir / "stderr.txt").read_text(errors="replace")
    if returncode != 0:
        return CaseOutcome("failed", returncode, error_line(stderr, stdout, returncode), wall_time)
    try:
        results = read_results(case_dir / RESULTS_IN_CASE)
    except ResultsError as error:
        return CaseOutcome("failed", returncode, f"no readable results: {error}", wall_time)
    if not study.timeseries_final and not results.summary:
        return CaseOutcome("failed", returncode, "no /summary rows (no beat completed)",
                           wall_time)
    return CaseOutcome("done", 0, "", wall_time)


def run_study(study: Study, out_dir: str | Path, parallel: int | None = None,
              ranks: int | None = None, command: list[str] | None = None,
              retry_failed: bool = False, stream=None, poll: float = 0.1) -> dict:
    """Run every unfinished case of the study, ``parallel`` at a time; write the table.

    Args:
        study: the parsed study file.
        out_dir: the study folder (created; resumed if it holds this study).
        parallel, ranks: override the study file's [run] values.
        command: the command of one case, with placeholders {prm} (the case file's
            absolute path), {ranks} and {case_dir}; run in the case folder, in its own
            process group. Default: ``systole {prm}``, under mpirun for ranks > 1.
        retry_failed: rerun the cases that failed before.
        stream: where the progress goes (default stdout).

    Returns:
        counts: {"done", "failed", "skipped", "run"} of this invocation.

    Raises:
        Interrupted: on SIGTERM or SIGINT, after stopping the running cases (they are
            rerun by the next invocation) and writing the table of what finished.
    """
    out_dir = Path(out_dir).resolve()
    parallel = parallel or study.parallel
    ranks = ranks or study.ranks
    command = command or default_command(ranks, find_systole())
    design = prepare(study, out_dir)
    lock = out_dir / "study.lock"
    if lock.exists():
        try:
            pid = int(lock.read_text())
            os.kill(pid, 0)
            raise StudyError(f"{out_dir} is being run by process {pid}")
        except (ValueError, ProcessLookupError, PermissionError):
            pass  # a stale lock of a study that was killed
    lock.write_text(str(os.getpid()))

    pending = []
    done = failed = skipped = 0
    for index in range(len(design)):
        case_dir = out_dir / "cases" / case_name(index)
        outcome = read_status(case_dir)
        if outcome is None or (retry_failed and outcome.status == "failed"):
            pending.append(index)
        else:
            skipped += 1
            done += outcome.status == "done"
            failed += outcome.status == "failed"
    progress = Progress(len(design), parallel, stream)
    progress.show(progress.line(done, failed, [], len(pending)),
                  f"[study] {out_dir.name}: {len(design)} cases, {skipped} finished before, "
                  f"{len(pending)} to run, {parallel} at a time with {ranks} rank(s) each")
    running: list[_Running] = []
    counts = {"done": 0, "failed": 0, "skipped": skipped, "run": 0}

    # The handler only records the signal: raising from it could interrupt Popen after
    # the fork, leaving a case running that the study does not know about.
    stop = []

    def on_signal(signum, frame):
        stop.append(signal.Signals(signum).name)

    old_handlers = {sig: signal.signal(sig, on_signal) for sig in (signal.SIGTERM, signal.SIGINT)}
    try:
        while pending or running:
            if stop:
                raise Interrupted(stop[0])
            while pending and len(running) < parallel and not stop:
                index = pending.pop(0)
                case_dir = out_dir / "cases" / case_name(index)
                (case_dir / "status.json").unlink(missing_ok=True)
                results_dir = case_dir / RESULTS_IN_CASE.parent
                if results_dir.exists():  # an interrupted or retried run: start afresh
                    shutil.rmtree(results_dir)
                args = [a.format(prm=case_dir / "case.prm", ranks=ranks, case_dir=case_dir)
                        for a in command]
                stdout = open(case_dir / "stdout.txt", "w")
                stderr = open(case_dir / "stderr.txt", "w")
                process = subprocess.Popen(args, cwd=case_dir, stdout=stdout, stderr=stderr,
                                           stdin=subprocess.DEVNULL, start_new_session=True)
                running.append(_Running(index, case_dir, process, stdout, stderr))
                counts["run"] += 1
                progress.show(progress.line(done, failed, running, len(pending)))
            time.sleep(poll)
            for job in list(running):
                returncode = job.process.poll()
                if returncode is None:
                    continue
                running.remove(job)
                job.stdout.close()
                job.stderr.close()
                wall = time.monotonic() - job.start
                outcome = _check_outcome(job.case_dir, returncode, wall, study)
                write_status(job.case_dir, outcome)
                progress.durations.append(wall)
                counts[outcome.status] += 1
                done += outcome.status == "done"
                failed += outcome.status == "failed"
                event = f"[study] {job.case_dir.name} {outcome.status} in {wall:.1f} s"
                if outcome.error:
                    event += f": {outcome.error}"
                progress.show(progress.line(done, failed, running, len(pending)), event)
            if progress.tty:
                progress.show(progress.line(done, failed, running, len(pending)))
    except Interrupted as signal_name:
        # A second signal while stopping the cases must not leave them running.
        for sig in old_handlers:
            signal.signal(sig, signal.SIG_IGN)
        for job in running:
            _stop(job.process)
            job.stdout.close()
            job.stderr.close()
        progress.show(progress.line(done, failed, [], len(pending) + len(running)),
                      f"[study] {signal_name}: stopped {len(running)} running case(s); "
                      "run the study again to resume")
        progress.finish()
        write_table(out_dir, gather(out_dir, study))
        raise
    finally:
        for sig, handler in old_handlers.items():
            signal.signal(sig, handler)
        lock.unlink(missing_ok=True)
    progress.finish()
    write_table(out_dir, gather(out_dir, study))
    return counts


# ----------------------------------------------------------------------------- the table


@dataclass
class Table:
    """The gathered study: column name -> list of values (one per row), units, metadata.

    ``parameter_entries`` maps each parameter column to its entry path, ``outputs`` lists
    the output columns (from /summary and final time-series values) in order.
    """

    columns: dict[str, list]
    units: dict[str, str]
    parameter_entries: dict[str, str]
    outputs: list[str]
    ranges: dict[str, tuple] = field(default_factory=dict)
    logs: dict[str, bool] = field(default_factory=dict)

    @property
    def n_rows(self) -> int:
        return len(self.columns["case"])

    def array(self, name: str) -> np.ndarray:
        return np.asarray(self.columns[name], dtype=float)


def gather(out_dir: str | Path, study: Study | None = None) -> Table:
    """Gather every case's parameters, status and /summary rows into one table.

    Unfinished cases have status "pending"; a case's missing outputs are NaN. With
    ``study`` None the study is read back from the folder's study.json.
    """
    out_dir = Path(out_dir)
    meta = json.loads((out_dir / "study.json").read_text())
    if study is None:
        study = _study_from_meta(out_dir, meta)
    design = meta["design"]
    names = [p.name for p in study.parameters]
    rows: list[dict] = []
    units: dict[str, str] = {"wall_time": "s"}
    outputs: list[str] = []
    for index, values in enumerate(design):
        case_dir = out_dir / "cases" / case_name(index)
        outcome = read_status(case_dir)
        base_row = {"case": case_name(index),
                    "status": outcome.status if outcome else "pending",
                    "error": outcome.error if outcome else "",
                    "wall_time": outcome.wall_time if outcome else math.nan}
        base_row.update({name: values[name] for name in names})
        summary_rows = [{}]
        if outcome is not None and outcome.status == "done":
            results = read_results(case_dir / RESULTS_IN_CASE)
            n_beats = len(next(iter(results.summary.values()), ()))
            beats = range(n_beats) if study.summary_rows == "all" else range(n_beats)[-1:]
            summary_rows = [{name: float(col[b]) for name, col in results.summary.items()}
                            for b in beats] or [{}]
            for name, unit in results.summary_units.items():
                units.setdefault(name, unit)
            final = {}
            for name in study.timeseries_final:
                if name in results.timeseries:
                    final["final_" + name] = float(results.timeseries[name][-1])
                    units.setdefault("final_" + name, results.units.get(name, ""))
            for name in study.statistics:
                if name in results.statistics:
                    final["statistics_" + name] = results.statistics[name]
            summary_rows = [row | final | _start_columns(results, row, study, units)
                            for row in summary_rows]
            if study.events:
                summary_rows = [row | _event_columns(case_dir / RESULTS_IN_CASE,
                                                     row.get("beat"), units)
                                for row in summary_rows]
        for row in summary_rows:
            for name in row:
                if name not in outputs:
                    outputs.append(name)
            rows.append(base_row | row)
    order = list(LEADING_COLUMNS) + names + outputs
    columns = {name: [row.get(name, math.nan) for row in rows] for name in order}
    for name in ("error",):
        columns[name] = [v if isinstance(v, str) else "" for v in columns[name]]
    return Table(columns=columns, units=units,
                 parameter_entries={p.name: p.entry_text for p in study.parameters},
                 outputs=outputs,
                 ranges={p.name: (p.low, p.high) for p in study.parameters
                         if p.low is not None},
                 logs={p.name: p.log for p in study.parameters})


def _start_columns(results, row: dict, study: Study, units: dict) -> dict:
    """start_<name>: the /timeseries column ``name`` when the row's beat starts (its
    /summary start_time; linear in time between the samples around it)."""
    start = row.get("start_time")
    if start is None:
        return {}
    columns = {}
    for name in study.timeseries_at_start:
        if name in results.timeseries and "time" in results.timeseries:
            columns["start_" + name] = float(np.interp(start, results.timeseries["time"],
                                                       results.timeseries[name]))
            units.setdefault("start_" + name, results.units.get(name, ""))
    return columns


def _event_columns(path: Path, beat, units: dict) -> dict:
    """The last event of each valve and direction in ``beat`` (all beats if None):
    valve<V>_<opens|closes>_<column> for every /events column but beat, valve and opens
    (valve<V>_<opens|closes>_time is the event's time)."""
    row = {}
    with h5py.File(path, "r") as h5file:
        if "events" not in h5file:
            return row
        events = {name: data[()] for name, data in h5file["events"].items()}
        event_units = {name: data.attrs.get("unit", b"") for name, data in
                       h5file["events"].items()}
    n = min(len(v) for v in events.values())
    for i in range(n):
        if beat is not None and events["beat"][i] != beat:
            continue
        prefix = f"valve{int(events['valve'][i])}_{'opens' if events['opens'][i] else 'closes'}"
        for name, values in events.items():
            if name in ("beat", "valve", "opens"):
                continue
            row[f"{prefix}_{name}"] = float(values[i])
            unit = event_units[name]
            units.setdefault(f"{prefix}_{name}",
                             unit.decode() if isinstance(unit, bytes) else str(unit))
    return row


def _study_from_meta(out_dir: Path, meta: dict) -> Study:
    parameters = [Parameter(p["name"], split_entry(p["entry"]), p["low"], p["high"],
                            log=p["log"]) for p in meta["parameters"]]
    text = meta.get("study", "")
    run = tomllib.loads(text).get("run", {}) if text else {}
    return Study(path=out_dir / meta.get("study_file", "study.toml"), base=Path(meta["base"]),
                 parameters=parameters, design={}, text=text,
                 summary_rows=run.get("summary_rows", "last"),
                 timeseries_final=list(run.get("timeseries_final", [])),
                 timeseries_at_start=list(run.get("timeseries_at_start", [])),
                 statistics=list(run.get("statistics", [])),
                 events=bool(run.get("events", False)))


def _is_text_column(values: list) -> bool:
    return any(isinstance(v, str) for v in values)


def write_table(out_dir: str | Path, table: Table) -> tuple[Path, Path]:
    """Write table.csv and table.h5 (group /table, one dataset per column) in ``out_dir``."""
    out_dir = Path(out_dir)
    csv_path, h5_path = out_dir / "table.csv", out_dir / "table.h5"
    names = list(table.columns)
    tmp = csv_path.with_suffix(".csv.tmp")
    with open(tmp, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(names)
        for i in range(table.n_rows):
            writer.writerow([_csv_value(table.columns[name][i]) for name in names])
    os.replace(tmp, csv_path)
    tmp = h5_path.with_suffix(".h5.tmp")
    with h5py.File(tmp, "w", track_order=True) as h5file:
        group = h5file.create_group("table", track_order=True)
        for name in names:
            values = table.columns[name]
            if _is_text_column(values):
                data = group.create_dataset(name, data=[str(v) for v in values],
                                            dtype=h5py.string_dtype("utf-8"))
            else:
                data = group.create_dataset(name, data=np.asarray(values, dtype=np.float64))
            data.attrs["unit"] = table.units.get(name, "")
            if name in table.parameter_entries:
                data.attrs["entry"] = table.parameter_entries[name]
                data.attrs["kind"] = "parameter"
                if name in table.ranges:
                    data.attrs["range"] = np.asarray(table.ranges[name], dtype=float)
                data.attrs["log"] = bool(table.logs.get(name, False))
            elif name in table.outputs:
                data.attrs["kind"] = "output"
    os.replace(tmp, h5_path)
    return csv_path, h5_path


def _csv_value(value) -> str:
    if isinstance(value, float):
        return "" if math.isnan(value) else repr(value)
    return str(value)


def read_table(path: str | Path) -> Table:
    """Read table.h5 back (a study folder or the file itself)."""
    path = Path(path)
    if path.is_dir():
        path = path / "table.h5"
    columns, units, entries, outputs, ranges, logs = {}, {}, {}, [], {}, {}
    with h5py.File(path, "r") as h5file:
        for name, data in h5file["table"].items():
            if data.dtype.kind in "OSU":
                columns[name] = [v.decode() if isinstance(v, bytes) else str(v) for v in data[()]]
            else:
                columns[name] = list(data[()])
            units[name] = str(data.attrs.get("unit", ""))
            kind = data.attrs.get("kind", "")
            if kind == "parameter":
                entries[name] = str(data.attrs["entry"])
                if "range" in data.attrs:
                    ranges[name] = tuple(float(v) for v in data.attrs["range"])
                logs[name] = bool(data.attrs.get("log", False))
            elif kind == "output":
                outputs.append(name)
    return Table(columns, units, entries, outputs, ranges, logs)


# ----------------------------------------------------------------------------- command line


def check_entries(study: Study, systole: str) -> None:
    """Refuse varied or [set] entries that Systole does not declare (``systole
    --print-parameters``)."""
    try:
        text = subprocess.run([systole, "--print-parameters"], capture_output=True, text=True,
                              check=True, timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        return  # no binary to ask: the cases will report the error
    known = parameter_paths(text)
    unknown = [p.entry_text for p in study.parameters if p.entry not in known]
    unknown += [" / ".join(entry) for entry in study.fixed if entry not in known]
    if unknown:
        raise StudyError(f"Systole declares no entry {', '.join(unknown)}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="systole-study", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command_name", required=True)
    run = sub.add_parser("run", help="run (or resume) a study")
    run.add_argument("study", help="the study file (TOML)")
    run.add_argument("-o", "--output", help="study folder (default: results/studies/<name>)")
    run.add_argument("--parallel", type=int, help="cases at a time (default: [run] parallel)")
    run.add_argument("--ranks", type=int, help="MPI ranks per case (default: [run] ranks)")
    run.add_argument("--retry-failed", action="store_true", help="rerun the failed cases")
    run.add_argument("--systole", help="the systole executable (default: $SYSTOLE_BUILD/systole)")
    run.add_argument("--command", help="the command of one case instead of systole, with "
                     "placeholders {prm}, {ranks}, {case_dir} (e.g. a fake runner in tests)")
    table = sub.add_parser("table", help="gather the table of a study folder again")
    table.add_argument("folder")
    sens = sub.add_parser("sensitivity", help="emulator, cross-validation and Sobol indices")
    sens.add_argument("folder")
    sens.add_argument("--output", action="append", required=True, dest="outputs",
                      help="an output column (repeatable), e.g. lv_EF")
    sens.add_argument("--samples", type=int, default=4096,
                      help="base samples of the Sobol estimator on the emulator")
    sens.add_argument("--seed", type=int, default=0)
    sens.add_argument("--no-plots", action="store_true")
    args = parser.parse_args(argv)
    try:
        if args.command_name == "run":
            study = load_study(args.study)
            out = Path(args.output or Path("results") / "studies" / study.path.stem)
            if args.command:
                command = shlex.split(args.command)
            else:
                systole = args.systole or find_systole()
                check_entries(study, systole)
                command = default_command(args.ranks or study.ranks, systole)
            try:
                counts = run_study(study, out, args.parallel, args.ranks, command,
                                   args.retry_failed)
            except Interrupted:
                return 130
            print(f"[study] {counts['run']} run ({counts['done']} done, {counts['failed']} "
                  f"failed), {counts['skipped']} finished before; table: {out / 'table.csv'}")
            return 0 if counts["failed"] == 0 else 1
        if args.command_name == "table":
            csv_path, _ = write_table(args.folder, gather(args.folder))
            print(csv_path)
            return 0
        from systole_post import sensitivity

        return sensitivity.main_for_study(args.folder, args.outputs, args.samples, args.seed,
                                          plots=not args.no_plots)
    except (StudyError, ResultsError, FileNotFoundError) as error:
        print(f"systole-study: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
