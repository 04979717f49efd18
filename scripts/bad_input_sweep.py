#!/usr/bin/env python3
"""Bad-input sweep: mutate the shipped parameter files and meshes and check that every
mutation stops systole with one clear line.

Parameter cases (run as `systole --check FILE`, which parses and validates and runs
nothing): each entry of each file in parameters/ gets a value of the wrong type, a value
outside its range, an empty value and a misspelt name; each subsection loses its
`subsection` line or its `end` line. The entry's pattern (type and bounds) comes from
`systole --print-parameters-json`.

Mesh cases (run as a one-step `Problem = cavity volume` on the mutated mesh, so that the
mesh is read, checked and used): a truncated file, a NaN, infinite or huge coordinate, an
inverted cell, a face tag removed or a face in two tags, an element naming a missing
node, a repeated node in a cell, a disconnected extra cell.

A free-text value (boundary part names, ...) that --check accepts is then run for real
for at most 15 s: it must stop at set-up, with one line and no results file.

Each outcome is classified:
  clear        exit != 0 and exactly one 'systole: error:' line that names the entry (or
               the line, for a broken subsection) or the mesh defect; no stack trace, no
               results file
  valid        exit 0 for a value that is valid after all (a listed entry where any value
               of the mutated kind is meaningful, or an empty value the pattern allows)
  accepted     exit 0 for an invalid value (a finding)
  unnamed      one error line that does not name the entry or defect
  multi-line   more than one error line, none, or a stack trace
  results      a results file left behind by a failed run
  crash        killed by a signal
  hang         still running after the time limit
Cases that fit none of these (an accepted value of a free-text entry, which only a
person can judge) are 'unclassified' and listed.

Deterministic: the cases are drawn with a fixed seed. Exit status 0 only when every case
is clear or valid.

Usage: bad_input_sweep.py --systole build/systole [--sample N] [--mesh-sample M]
       [--kinds params,meshes] [--json out.json]
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: Entries where any real number is a meaningful value (coordinates, times, offsets,
#: signed angles, ...): an accepted out-of-range value there is no finding. Matched
#: against the end of "Section / Entry".
ANY_REAL = [
    "Time / Start time", "Time / End time",
    "Box / Lower corner", "Box / Upper corner",
    "Local refinement center", "Base height", "Apex",
    "angle", "Angle", "Helix", "helix", "Offset", "offset", "Shift", "shift",
    "Translation", "Image to mesh transform", "Rotation",
    "potential", "Potential",  # membrane potentials in mV are signed
    "threshold",  # Activation threshold: a potential in mV
    "Mechanics / Pressure",  # a negative cavity pressure is suction
    "Initial pressure",  # transmural pressures of 0D compartments are signed
    "Initial flow",  # flows reverse
]

#: Free-text entries where any text is a meaningful value: the run's folder name (any
#: name without '/', which is checked).
FREE_TEXT_VALID = ["Output / Run name"]

#: Pattern kinds whose empty value may be valid (lists, maps, free text).
EMPTY_OK = ("List", "Map", "Anything", "FileName", "DirectoryName")


@dataclass
class Case:
    kind: str  # "params" or "meshes"
    label: str
    mutation: str
    entry: str = ""  # "Section / Entry" or the mesh defect's keywords
    expect: list[str] = field(default_factory=list)  # words the error line must contain
    text: str = ""  # the mutated parameter file
    mesh_text: bytes = b""  # the mutated mesh file
    mesh_name: str = ""
    base_prm: str = ""  # for mesh cases: the parameter file that reads the mesh
    pattern: str = ""
    allowed_if_accepted: bool = False  # exit 0 means "valid", not a finding
    free_text: bool = False  # exit 0 can only be judged by a person


# --------------------------------------------------------------------------------------
# Parameter files


def declarations(systole: Path, cwd: Path, saved: Path | None = None) -> dict[str, str]:
    """'Section / Entry' -> pattern description, from --print-parameters-json (or from
    @p saved, its output kept from another build)."""
    if saved:
        out = saved.read_text()
    else:
        out = subprocess.run([str(systole), "--print-parameters-json"], cwd=cwd,
                             check=True, capture_output=True, text=True).stdout
    tree = json.loads(out)
    patterns: dict[str, str] = {}

    def walk(node: dict, path: list[str]) -> None:
        for key, value in node.items():
            if not isinstance(value, dict):
                continue
            name = key
            if "pattern_description" in value:
                patterns[" / ".join(path + [name])] = value["pattern_description"]
            else:
                walk(value, path + [name])

    walk(tree, [])
    return patterns


def entries_of(text: str) -> tuple[list[tuple[int, list[str], str, str]],
                                   list[tuple[int, int, list[str]]]]:
    """The 'set' lines (line index, subsection path, name, value) and the subsections
    (index of 'subsection' line, index of its 'end' line, path) of a .prm text."""
    sets, sections, stack = [], [], []
    for i, line in enumerate(text.splitlines()):
        code = line.split("#", 1)[0].strip()
        if code.startswith("subsection "):
            stack.append((i, code[len("subsection "):].strip()))
        elif code == "end" and stack:
            start, name = stack.pop()
            sections.append((start, i, [s for _, s in stack] + [name]))
        elif code.startswith("set ") and "=" in code:
            name, value = code[4:].split("=", 1)
            sets.append((i, [s for _, s in stack], name.strip(), value.strip()))
    return sets, sections


def number_bounds(pattern: str) -> tuple[str, float | None, float | None] | None:
    """('Double' or 'Integer', lower, upper) of a plain number pattern, None if unbounded
    on a side; None if the pattern is no plain number."""
    m = re.fullmatch(r"\[(Double|Integer)(?: range)? ?(\S*?)\.\.\.(\S*?) \(inclusive\)\]",
                     pattern.strip())
    if not m:
        if pattern.strip() in ("[Double -MAX_DOUBLE...MAX_DOUBLE (inclusive)]",):
            return ("Double", None, None)
        m2 = re.fullmatch(r"\[(Double|Integer)\]", pattern.strip())
        return (m2.group(1), None, None) if m2 else None
    kind, lo, hi = m.group(1), m.group(2), m.group(3)

    def value(s: str) -> float | None:
        if "MAX" in s or s == "":
            return None
        return float(s)

    return kind, value(lo), value(hi)


def pattern_kind(pattern: str) -> str:
    m = re.match(r"\[(\w+)", pattern.strip())
    return m.group(1) if m else "Anything"


def misspell(name: str, rng: random.Random) -> str:
    """Swap two neighbouring letters that differ (a typo), or drop one."""
    spots = [i for i in range(len(name) - 1)
             if name[i].isalpha() and name[i + 1].isalpha() and name[i] != name[i + 1]]
    if not spots:
        return name + "x"
    i = rng.choice(spots)
    return name[:i] + name[i + 1] + name[i] + name[i + 2:]


def replace_value(lines: list[str], index: int, name: str, value: str) -> str:
    indent = re.match(r"\s*", lines[index]).group(0)
    new = lines.copy()
    new[index] = f"{indent}set {name} = {value}" if value else f"{indent}set {name} ="
    return "\n".join(new) + "\n"


def parameter_cases(root: Path, patterns: dict[str, str], rng: random.Random) -> list[Case]:
    cases: list[Case] = []
    for prm in sorted((root / "parameters").glob("*.prm")):
        text = prm.read_text()
        lines = text.splitlines()
        sets, sections = entries_of(text)
        label = prm.name
        for index, path, name, value in sets:
            key = " / ".join(path + [name])
            pattern = patterns.get(key, "")
            if not pattern:
                continue  # an unknown entry in a shipped file: the --check test's business
            kind = pattern_kind(pattern)
            where = f"{label}:{index + 1} {key}"
            # A misspelt name.
            typo = misspell(name, rng)
            new = lines.copy()
            new[index] = lines[index].replace(name, typo, 1)
            cases.append(Case("params", where, "misspelt name", key, [typo],
                              "\n".join(new) + "\n", pattern=pattern))
            # A value of the wrong type.
            wrong = {"Double": "abc", "Integer": "2.5", "Bool": "maybe",
                     "Selection": "no_such_choice", "List": "1, no such item, ;",
                     "Map": "no map", "FileName": "no_such_file.msh"}.get(kind)
            if wrong is not None:
                cases.append(Case("params", where, "wrong type", key, [name],
                                  replace_value(lines, index, name, wrong), pattern=pattern,
                                  allowed_if_accepted=kind in ("List", "Map")))
            else:
                cases.append(Case("params", where, "wrong type", key, [name],
                                  replace_value(lines, index, name, "@@ not a value ("),
                                  pattern=pattern, free_text=True,
                                  allowed_if_accepted=key in FREE_TEXT_VALID))
            if "Type: output" in pattern:  # any folder name is an output folder
                cases[-1].allowed_if_accepted = True
            # Out of range.
            bounds = number_bounds(pattern)
            if bounds:
                number, lo, hi = bounds
                if lo is not None:
                    bad = lo - max(1.0, abs(lo))
                elif hi is not None:
                    bad = hi + max(1.0, abs(hi))
                else:
                    try:
                        current = float(value)
                    except ValueError:
                        current = 1.0
                    bad = -1e30 if current > 0 else 1e30
                text_bad = str(int(bad)) if number == "Integer" else repr(bad)
                valid = lo is None and hi is None and any(key.endswith(a) or a in key
                                                          for a in ANY_REAL)
                cases.append(Case("params", where, "out of range", key, [name],
                                  replace_value(lines, index, name, text_bad),
                                  pattern=pattern, allowed_if_accepted=valid))
            # Empty.
            cases.append(Case("params", where, "empty", key, [name],
                              replace_value(lines, index, name, ""), pattern=pattern,
                              allowed_if_accepted=kind in EMPTY_OK))
        for start, end, path in sections:
            where = f"{label}:{start + 1} subsection {' / '.join(path)}"
            for drop, what in ((start, "missing subsection line"), (end, "missing end line")):
                new = [l for i, l in enumerate(lines) if i != drop]
                cases.append(Case("params", where, what, " / ".join(path),
                                  ["line", "subsection", "end"], "\n".join(new) + "\n"))
    return cases


# --------------------------------------------------------------------------------------
# Meshes (gmsh 2.2 ASCII: $Nodes "id x y z", $Elements "id type ntags tags... nodes")


MESH_PRM = """# Bad-input sweep: read, check and use a mutated mesh for one step.
set Problem = cavity volume
subsection Geometry
  set Type = gmsh
  subsection Gmsh
    set Mesh file = {mesh}
{names}  end
end
{kinematics}subsection Time
  set End time  = 10
  set Time step = 10
end
subsection Output
  set Run name              = mesh_case
  set Field output interval = 0
end
"""

#: The small shipped meshes the mesh cases start from, with what a cavity-volume run
#: needs from each.
MESHES = {
    "lv_coarse.msh": ("", ""),
    "biv_hex_coarse.msh": ("", "subsection Kinematics\n  set Cavities = lv_endocardium, "
                               "rv_endocardium\nend\n"),
    "lv_ellipsoid_tet.msh": ("    set Boundary names = base: BASE; endocardium: ENDO; "
                             "epicardium: EPI\n", ""),
}


def sections_22(text: str) -> dict[str, tuple[int, int]]:
    """Line ranges (first line after the header, the $End line) of each section."""
    lines = text.split("\n")
    out, open_name, open_at = {}, None, 0
    for i, l in enumerate(lines):
        if l.startswith("$End"):
            out[open_name] = (open_at, i)
            open_name = None
        elif l.startswith("$"):
            open_name, open_at = l[1:].strip(), i + 1
    return out


def mesh_cases(root: Path, rng: random.Random) -> list[Case]:
    cases: list[Case] = []
    for mesh, (names, kinematics) in MESHES.items():
        raw = (root / "meshes" / mesh).read_bytes()
        prm = MESH_PRM.format(mesh="{mesh}", names=names, kinematics=kinematics)

        def add(mutation: str, data: bytes, expect: list[str]) -> None:
            cases.append(Case("meshes", f"{mesh}: {mutation}", mutation, mesh, expect,
                              mesh_text=data, mesh_name=mesh, base_prm=prm))

        for fraction in (0.02, 0.3, 0.6, 0.9, 0.999):
            add(f"truncated at {fraction:.1%}", raw[: int(len(raw) * fraction)],
                [mesh, "read|truncated|end"])
        text = raw.decode()
        if not text.split("\n")[1].startswith("2.2"):
            continue
        lines = text.split("\n")
        sec = sections_22(text)
        n0, n1 = sec["Nodes"]
        nodes = list(range(n0 + 1, n1))
        e0, e1 = sec["Elements"]
        elements = list(range(e0 + 1, e1))
        volumes = [i for i in elements if lines[i].split()[1] in ("4", "5")]
        faces = [i for i in elements if lines[i].split()[1] in ("2", "3")]

        def with_lines(changes: dict[int, str | None], extra_after: dict[int, list[str]]
                       | None = None) -> bytes:
            new = []
            for i, l in enumerate(lines):
                if i in changes:
                    if changes[i] is not None:
                        new.append(changes[i])
                else:
                    new.append(l)
                for x in (extra_after or {}).get(i, []):
                    new.append(x)
            return "\n".join(new).encode()

        for value, what in (("nan", "NaN"), ("inf", "infinite"), ("1e300", "huge"),
                            ("-1e300", "huge")):
            for _ in range(2):
                i = rng.choice(nodes)
                f = lines[i].split()
                f[1 + rng.randrange(3)] = value
                add(f"node {f[0]}: {what} coordinate {value}",
                    with_lines({i: " ".join(f)}), [mesh, rf"node {f[0]}\b"])
        for _ in range(3):
            i = rng.choice(volumes)
            f = lines[i].split()
            ntags = int(f[2])
            conn = f[3 + ntags:]
            half = len(conn) // 2
            # Hexahedra: bottom and top swapped; tetrahedra: two nodes swapped.
            conn = conn[half:] + conn[:half] if len(conn) == 8 else [conn[1], conn[0]] + conn[2:]
            add(f"element {f[0]}: inverted", with_lines({i: " ".join(f[:3 + ntags] + conn)}),
                [mesh, "invert|Jacobian|volume"])
        for _ in range(2):
            i = rng.choice(volumes)
            f = lines[i].split()
            ntags = int(f[2])
            f[3 + ntags + 1] = f[3 + ntags]
            add(f"element {f[0]}: a node twice", with_lines({i: " ".join(f)}),
                [mesh, rf"(element|cell) {f[0]}\b"])
            i = rng.choice(volumes)
            f = lines[i].split()
            f[-1] = "999999"
            add(f"element {f[0]}: a missing node", with_lines({i: " ".join(f)}),
                [mesh, r"node (index )?999999"])
        tags = sorted({lines[i].split()[3] for i in faces})
        names_of = {}
        p0, p1 = sec.get("PhysicalNames", (0, 0))
        for i in range(p0 + 1, p1):
            f = lines[i].split()
            if f[0] == "2":
                names_of[f[1]] = f[2].strip('"')
        for tag in tags:
            name = names_of.get(tag, tag)
            removed = {i: None for i in faces if lines[i].split()[3] == tag}
            n_el = len(elements) - len(removed)
            removed[e0] = str(n_el)
            add(f"face tag {tag} ({name}) removed", with_lines(removed), [mesh, name])
            # A cavity-volume run uses no epicardium: that part may go.
            cases[-1].allowed_if_accepted = name == "epicardium"
        for _ in range(2):
            i = rng.choice(faces)
            f = lines[i].split()
            other = rng.choice([t for t in tags if t != f[3]])
            g = f.copy()
            g[0] = str(10 ** 7)
            g[3] = other
            changes = {e0: str(len(elements) + 1)}
            add(f"face {f[0]} also in tag {other}",
                with_lines(changes, {i: [" ".join(g)]}), [mesh, "face tag .* and face tag"])
        # A disconnected piece: a copy of one cell, moved far away.
        i = rng.choice(volumes)
        f = lines[i].split()
        ntags = int(f[2])
        conn = f[3 + ntags:]
        coords = {lines[j].split()[0]: lines[j].split()[1:] for j in nodes}
        new_nodes, new_conn = [], []
        for k, node in enumerate(conn):
            nid = str(10 ** 7 + k)
            x, y, z = (float(c) for c in coords[node])
            new_nodes.append(f"{nid} {x + 1000.0} {y} {z}")
            new_conn.append(nid)
        changes = {n0: str(len(nodes) + len(conn)), e0: str(len(elements) + 1)}
        extra = {n1 - 1: new_nodes,
                 e1 - 1: [" ".join([str(10 ** 7)] + f[1:3 + ntags] + new_conn)]}
        add("a disconnected cell 1000 mm away", with_lines(changes, extra),
            [mesh, "disconnected"])
    return cases


# --------------------------------------------------------------------------------------
# Running and classifying


def run_setup(case: Case, systole: Path, work: Path, timeout: float) -> tuple[str, str]:
    """A free-text value that --check accepted, run for real for at most @p timeout
    seconds: 'clear' if it stops with one line naming the entry and no results file."""
    shutil.rmtree(work / "results", ignore_errors=True)
    process = subprocess.Popen([str(systole), "parameters/_sweep_case.prm"], cwd=work,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                               errors="replace", start_new_session=True)
    try:
        _, stderr = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        return "unclassified", f"accepted by --check; still setting up after {timeout:g} s"
    errors = re.findall(r"^systole: error: .*$", stderr, re.MULTILINE)
    results = any((work / "results").rglob("results.h5")) if (work / "results").exists() \
        else False
    if process.returncode == 0:
        return "accepted", "ran to the end"
    if process.returncode < 0:
        return "crash", f"signal {-process.returncode} at set-up"
    if len(errors) != 1:
        return "multi-line", f"{len(errors)} error lines at set-up"
    if results:
        return "results", errors[0]
    named = any(w.lower() in errors[0].lower() for w in case.expect)
    return ("clear" if named else "unnamed"), errors[0] + " (at set-up)"


def run_case(case: Case, systole: Path, work: Path, timeout: float,
             setup_timeout: float = 15.0) -> tuple[str, str]:
    """(class, the error line or a note)."""
    folder = work / "case"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir()
    if case.kind == "params":
        prm = work / "parameters" / "_sweep_case.prm"
        prm.write_text(case.text)
        command = [str(systole), "--check", str(prm.relative_to(work))]
        cwd = work
    else:
        mesh = folder / case.mesh_name
        mesh.write_bytes(case.mesh_text)
        (folder / "mesh_case.prm").write_text(case.base_prm.replace("{mesh}", case.mesh_name))
        command = [str(systole), "mesh_case.prm"]
        cwd = folder
    process = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, errors="replace", start_new_session=True)
    try:
        stdout, stderr = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        return "hang", f"still running after {timeout:g} s"
    rc = process.returncode
    if rc < 0:
        last = stderr.strip().splitlines()[-1:] or [""]
        return "crash", f"signal {-rc}: {last[0][:200]}"
    errors = re.findall(r"^systole: error: .*$", stderr, re.MULTILINE)
    if rc == 0:
        if case.allowed_if_accepted:
            return "valid", "accepted"
        if case.free_text:
            # Names checked against the mesh (boundary parts) pass --check: the run
            # must stop at its set-up, before any results are written.
            return run_setup(case, systole, work, setup_timeout)
        return "accepted", "exit 0"
    if len(errors) != 1 or re.search("Stacktrace|An error occurred in line", stderr):
        return "multi-line", f"{len(errors)} error lines: " + " | ".join(
            stderr.strip().splitlines()[:3])[:300]
    line = errors[0]
    if (folder / "results").exists() and any((folder / "results").rglob("results.h5")):
        return "results", line
    words = [w for w in case.expect if w]
    if case.kind == "params" and case.mutation.startswith("missing"):
        ok = bool(re.search(r"line \d+", line))
    elif case.kind == "params":
        ok = any(w.lower() in line.lower() for w in words)
    else:
        # The file's name, and the defect (a regular expression of alternatives).
        ok = words[0].lower() in line.lower() and all(
            re.search(w, line, re.IGNORECASE) for w in words[1:])
    return ("clear" if ok else "unnamed"), line


SECTION_TITLE = "Bad input swept (scripts/bad_input_sweep.py)"
CLASSES = ("clear", "valid", "accepted", "unnamed", "multi-line", "results", "crash", "hang",
           "unclassified")


def mutation_kind(outcome: dict) -> str:
    """The row of the summary table an outcome counts in."""
    if outcome["kind"] == "params":
        return "parameters: " + outcome["mutation"]
    m = outcome["mutation"]
    for word in ("truncated", "NaN", "infinite", "huge", "inverted", "a node twice",
                 "a missing node", "removed", "also in tag", "disconnected"):
        if word in m:
            return "meshes: " + {"also in tag": "a face in two tags",
                                 "removed": "a face tag removed"}.get(word, word)
    return "meshes: " + m


def markdown(outcomes: list[dict], seconds: float, seed: int, command: str) -> str:
    """The docs/verification.md section of a sweep."""
    rows: dict[str, dict[str, int]] = {}
    for o in outcomes:
        rows.setdefault(mutation_kind(o), collections.Counter())[o["class"]] += 1
    used = [c for c in CLASSES if any(r[c] for r in rows.values())]
    lines = [f"## {SECTION_TITLE}",
             f"Written by `{command}` ({len(outcomes)} cases, seed {seed}, "
             f"{seconds:.0f} s on 1 core). Each case is one mutation of a shipped parameter "
             "file (run as `systole --check`) or of a shipped mesh (read by a one-step cavity-"
             "volume run); classes as in the script's help: *clear* = exit 1 with one line "
             "naming the entry or defect, *valid* = accepted and meaningful (a signed "
             "quantity, an empty list, an unused part removed).", "",
             "| mutation | cases | " + " | ".join(used) + " |",
             "|---|---|" + "---|" * len(used)]
    for name in sorted(rows):
        r = rows[name]
        lines.append(f"| {name} | {sum(r.values())} | " +
                     " | ".join(str(r[c]) for c in used) + " |")
    total = collections.Counter(o["class"] for o in outcomes)
    lines.append(f"| **all** | {len(outcomes)} | " +
                 " | ".join(f"**{total[c]}**" for c in used) + " |")
    odd = [o for o in outcomes if o["class"] not in ("clear", "valid")]
    if odd:
        lines += ["", "Not clear:", ""]
        lines += [f"- {o['class']}: {o['case']} ({o['mutation']}): {o['message'][:200]}"
                  for o in odd]
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--systole", type=Path, required=True)
    parser.add_argument("--source", type=Path, default=ROOT)
    parser.add_argument("--sample", type=int, default=0,
                        help="run this many parameter cases, drawn with the seed (0: all)")
    parser.add_argument("--mesh-sample", type=int, default=0,
                        help="run this many mesh cases, drawn with the seed (0: all)")
    parser.add_argument("--kinds", default="params,meshes")
    parser.add_argument("--mutations", default="",
                        help="only these parameter mutations (comma-separated, e.g. "
                             "'out of range,empty')")
    parser.add_argument("--seed", type=int, default=42)
    parser.add_argument("--timeout", type=float, default=30.0, help="per case [s]")
    parser.add_argument("--json", type=Path, help="write every outcome here")
    parser.add_argument("--markdown", type=Path,
                        help="write the docs/verification.md section of the sweep here")
    parser.add_argument("--declarations", type=Path,
                        help="the output of 'systole --print-parameters-json' to use (for "
                             "an older systole without that option)")
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    systole = args.systole.resolve()
    rng = random.Random(args.seed)
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="systole-sweep-") as tmp:
        work = Path(tmp)
        shutil.copytree(args.source / "parameters", work / "parameters",
                        ignore=shutil.ignore_patterns("studies"))
        (work / "meshes").symlink_to((args.source / "meshes").resolve())
        cases: list[Case] = []
        kinds = args.kinds.split(",")
        if "params" in kinds:
            pc = parameter_cases(args.source, declarations(systole, work, args.declarations), rng)
            if args.mutations:
                pc = [c for c in pc if c.mutation in args.mutations.split(",")]
            if args.sample:
                pc = random.Random(args.seed).sample(pc, min(args.sample, len(pc)))
            cases += pc
        if "meshes" in kinds:
            mc = mesh_cases(args.source, rng)
            if args.mesh_sample:
                mc = random.Random(args.seed).sample(mc, min(args.mesh_sample, len(mc)))
            cases += mc
        outcomes = []
        for n, case in enumerate(cases):
            t0 = time.monotonic()
            klass, note = run_case(case, systole, work, args.timeout)
            outcomes.append({"kind": case.kind, "case": case.label, "mutation": case.mutation,
                             "class": klass, "message": note,
                             "seconds": round(time.monotonic() - t0, 2)})
            if args.verbose:
                print(f"[{n + 1}/{len(cases)}] {klass:12s} {case.label} ({case.mutation}): "
                      f"{note}", flush=True)
    elapsed = time.monotonic() - start
    counts = collections.Counter((o["kind"], o["class"]) for o in outcomes)
    print(f"Bad-input sweep: {len(outcomes)} cases in {elapsed:.1f} s (seed {args.seed})")
    for kind in ("params", "meshes"):
        row = {k: v for (kd, k), v in counts.items() if kd == kind}
        if row:
            print(f"  {kind}: " + ", ".join(f"{k} {v}" for k, v in sorted(row.items())))
    by_mutation = collections.Counter((mutation_kind(o), o["class"]) for o in outcomes)
    if args.verbose:
        for (m, k), v in sorted(by_mutation.items()):
            print(f"    {m}: {k} {v}")
    bad = [o for o in outcomes if o["class"] not in ("clear", "valid")]
    for o in bad:
        print(f"  {o['class']}: {o['case']} ({o['mutation']}): {o['message']}")
    if args.json:
        args.json.write_text(json.dumps({"seed": args.seed, "seconds": elapsed,
                                         "outcomes": outcomes}, indent=1))
    if args.markdown:
        command = "python3 scripts/bad_input_sweep.py --systole build/systole" + (
            f" --sample {args.sample}" if args.sample else "") + (
            f" --mesh-sample {args.mesh_sample}" if args.mesh_sample else "")
        args.markdown.write_text(markdown(outcomes, elapsed, args.seed, command))
    return 0 if not bad else 1


if __name__ == "__main__":
    sys.exit(main())
