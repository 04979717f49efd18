#!/usr/bin/env python3
"""Check that docs/architecture.md names only things that exist.

Every backticked name is checked by its kind:
- a parameter path (`Subsection / Entry`, optionally `= value`): the path, or its tail, is a
  subsection or an entry of docs/parameters.prm;
- a file (has a slash or a known extension; `a.{h,cc}` expands): it exists relative to the
  repository root or to src/, or (a bare file name) somewhere in the repository;
- a code name (a capitalised or snake_case identifier, `A::B`, `f(...)`): every part occurs as a word in src/, apps/ or tests/;
- anything else (values, formulas, prose) is not checked.
Links to `verification.md#anchor` must match a heading of docs/verification.md (GitHub's anchor
rules), and a markdown link to a file must point to an existing file.
Usage: python3 scripts/check_docs.py [--max-lines N] [FILE.md ...]; exit status 1 lists every
stale name (and a file longer than N lines: the map must stay a map).
"""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXTENSIONS = (".h", ".cc", ".py", ".prm", ".msh", ".md", ".txt", ".toml", ".json", ".geo")
IGNORED_PREFIXES = ("results/", "build/", ".venv", "/", ".")  # outputs, HDF5 paths, extensions
#: files a run writes, named in the docs as outputs
OUTPUTS = {"calibrated.prm", "case.prm", "checkpoint.tmp/", "results.h5", "fields.xdmf", "report.html",
           "paraview.png", "state.bin", "unloaded.msh"}
CODE_DIRS = ("src", "apps", "tests")


def parameter_paths() -> set[tuple[str, ...]]:
    """Every subsection and entry of docs/parameters.prm as a tuple of names."""
    paths, stack = set(), []
    for line in (ROOT / "docs" / "parameters.prm").read_text().splitlines():
        line = line.strip()
        if line.startswith("subsection "):
            stack.append(line[len("subsection "):].strip())
            paths.add(tuple(stack))
        elif line == "end":
            stack.pop()
        elif line.startswith("set "):
            paths.add(tuple(stack) + (line[4:].split("=")[0].strip(),))
    return paths


def code_words() -> set[str]:
    words = set()
    for folder in CODE_DIRS:
        for path in (ROOT / folder).rglob("*"):
            if path.suffix in (".h", ".cc", ".py", ".txt", ".in") and path.is_file():
                words.update(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", path.read_text(errors="ignore")))
    return words


def anchors(markdown: Path) -> set[str]:
    """GitHub's anchors of the headings: lower case, punctuation dropped, spaces to '-'."""
    seen, result = {}, set()
    for line in markdown.read_text().splitlines():
        if line.startswith("#"):
            anchor = re.sub(r"[^\w\- ]", "", line.lstrip("#").strip().lower()).replace(" ", "-")
            count = seen.get(anchor, 0)
            seen[anchor] = count + 1
            result.add(anchor if count == 0 else f"{anchor}-{count}")
    return result


def expand(name: str) -> list[str]:
    match = re.search(r"\{([^}]*)\}", name)
    if not match:
        return [name]
    return [name[:match.start()] + part + name[match.end():] for part in match.group(1).split(",")]


def file_exists(name: str, all_files: dict[str, list[Path]]) -> bool:
    for candidate in expand(name):
        if candidate.endswith("/") or "/" in candidate:
            if not any((base / candidate).exists() for base in (ROOT, ROOT / "src")):
                return False
        elif candidate not in all_files:
            return False
    return True


def is_file_like(name: str) -> bool:
    if (" " in name or name.startswith(IGNORED_PREFIXES) or "<" in name or "NNN" in name
            or name in OUTPUTS):
        return False
    if "::" in name or "(" in name:
        return False
    return "/" in name or name.endswith(EXTENSIONS) or re.search(r"\.\{[\w,]+\}$", name) is not None


def check(doc: Path) -> list[str]:
    text = doc.read_text()
    params = parameter_paths()
    words = code_words()
    all_files: dict[str, list[Path]] = {}
    for path in ROOT.rglob("*"):
        if ".git" not in path.parts and "build" not in path.parts and path.is_file():
            all_files.setdefault(path.name, []).append(path)
    problems = []
    # fenced blocks are not names; keep their newlines for the line numbers
    text = re.sub(r"^```.*?^```", lambda m: "\n" * m.group(0).count("\n"), text,
                  flags=re.MULTILINE | re.DOTALL)
    for match in re.finditer(r"`([^`]+)`", text):
        name = " ".join(match.group(1).split())  # a name may wrap onto the next line
        number = text.count("\n", 0, match.start()) + 1
        if " / " in name:
            parts = tuple(p.strip() for p in name.split("=")[0].split(" / "))
            if not any(path[-len(parts):] == parts for path in params):
                problems.append(f"{doc.name}:{number}: parameter `{name}` not in docs/parameters.prm")
        elif is_file_like(name):
            if not file_exists(name, all_files):
                problems.append(f"{doc.name}:{number}: file `{name}` does not exist")
        elif re.fullmatch(r"[A-Za-z_][\w:]*\(.*\)", name):  # a call: check the callee
            for part in name.split("(")[0].split("::"):
                if part and part not in words:
                    problems.append(f"{doc.name}:{number}: code name `{name}` ({part}) not found")
        elif re.fullmatch(r"[A-Za-z_][\w:]*", name) and (
                "::" in name or name[0].isupper() or "_" in name):
            for part in name.split("::"):
                if part and part not in words:
                    problems.append(f"{doc.name}:{number}: code name `{name}` ({part}) not found")
    for number, line in enumerate(text.splitlines(), 1):
        if re.search(r"\]\([^)]*$", line):
            problems.append(f"{doc.name}:{number}: a link target wraps onto the next line")
        for target in re.findall(r"\]\(([^)\s]+)\)", line):
            if target.startswith(("http://", "https://")):
                continue
            file_part, _, anchor = target.partition("#")
            path = (doc.parent / file_part) if file_part else doc
            if not path.exists():
                problems.append(f"{doc.name}:{number}: link to missing file {file_part}")
            elif anchor and path.suffix == ".md" and anchor not in anchors(path):
                problems.append(f"{doc.name}:{number}: no heading #{anchor} in {path.name}")
    return problems


def main() -> int:
    args = sys.argv[1:]
    max_lines = None
    if args[:1] == ["--max-lines"]:
        max_lines, args = int(args[1]), args[2:]
    docs = [Path(a).resolve() for a in args] or [ROOT / "docs" / "architecture.md"]
    problems = [p for doc in docs for p in check(doc)]
    if max_lines is not None:
        problems += [f"{doc.name}: {n} lines, more than {max_lines}" for doc in docs
                     if (n := len(doc.read_text().splitlines())) > max_lines]
    for problem in problems:
        print(problem, file=sys.stderr)
    if not problems:
        print("docs ok")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
