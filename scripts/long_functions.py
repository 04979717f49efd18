#!/usr/bin/env python3
"""List the long functions of the C++ sources (issue 39: a function fits a screen).

A brace-matching scan, not a parser: comments, string and character literals and preprocessor
lines are blanked, then every `{` at namespace or class level is classified by the text before it
(since the last `;`, `{` or `}` of a body at that level). A block that follows `)`, a
`const`/`override`/`noexcept`/... qualifier or a trailing return type is a function body (free,
member, lambda at namespace level); `namespace`, `class`, `struct`, `union`, `enum` and
`extern "C"` open containers the scan descends into; anything else (a brace initialiser) is
skipped. A function's length runs from the first line of its declaration (template line included)
to its closing brace.

With --members M it lists instead the classes and structs with more than M non-static data
members (issue 39: a class of one job). The same blanked text is walked recursively: in a class
body every statement ending in `;` at class level is a declaration; those with a top-level `(`
before any initialiser (functions, `= default`), `static`, `using`, `typedef`, `friend`,
`template` and forward declarations are skipped; the others count one member per top-level
declarator (`double a, b;` is two). Nested classes are counted on their own (`Outer::Inner`).

Usage: python3 scripts/long_functions.py [--max-lines N] [--top K] [--members M] [PATH ...]
(default: src/ with N = 120). Prints the functions longer than N lines (or the classes with more
than M data members), largest first, then their count; exit status is always 0 (a report, not a
gate).
"""

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
QUALIFIERS = ("const", "override", "final", "noexcept", "mutable", "try")
CONTAINER = re.compile(r"^\s*(template\s*<.*>\s*)?(namespace|class|struct|union|enum)\b|^\s*extern\s*\"C\"",
                       re.S)


def blank(text: str) -> str:
    """The text with comments, literals and preprocessor lines replaced by spaces (newlines kept)."""
    out, i, n = [], 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":
            j = i
            while j < n and (text[j] != "\n" or text[j - 1] == "\\"):
                j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        if c == "\n":
            at_line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            at_line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append('""' + re.sub(r"[^\n]", " ", text[i + 2:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + re.sub(r"[^\n]", " ", text[i + 1:j - 1]) + c if j - i >= 2 else c)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def function_name(header: str) -> str:
    """The (qualified) name before the parameter list, or '<lambda>' / '?'."""
    paren = header.find("(")
    if paren < 0:
        return "?"
    before = header[:paren]
    if "[" in before:
        m = re.search(r"([A-Za-z_]\w*)\s*=\s*\[", header)
        return (m.group(1) if m else "<lambda>") + " (lambda)"
    m = re.search(r"((?:[A-Za-z_~]\w*\s*(?:<[^<>()]*>)?\s*::\s*)*(?:operator\s*[^\s(]+|[A-Za-z_~]\w*))\s*$",
                  before)
    return re.sub(r"\s+", "", m.group(1)) if m else "?"


def is_function_body(header: str) -> bool:
    stripped = header.rstrip()
    if "(" not in stripped:
        return False
    if stripped.endswith(")"):
        return True
    last_word = re.search(r"(\w+)\s*$", stripped)
    if last_word and last_word.group(1) in QUALIFIERS:
        return True
    if "->" in stripped[stripped.rfind(")"):]:
        return True
    # a constructor whose initialiser list ends with a brace initialiser: `A() : x{1} {`
    return stripped.endswith("}") and ":" in stripped


def line_numbers(code: str):
    """The line (from 1) of every character of code, and of its end."""
    line_of = [0] * (len(code) + 1)
    line = 1
    for k, ch in enumerate(code):
        line_of[k] = line
        if ch == "\n":
            line += 1
    line_of[len(code)] = line
    return line_of


def scan(text: str):
    """Yield (first line, last line, name) of every function body at namespace or class level."""
    code = blank(text)
    line_of = line_numbers(code)
    header_start, i, n = 0, 0, len(code)
    while i < n:
        c = code[i]
        if c == ";":
            header_start = i + 1
        elif c == "}":
            header_start = i + 1  # end of a container
        elif c == "{":
            header = code[header_start:i]
            if CONTAINER.match(header) and "(" not in header:
                header_start = i + 1  # descend
            else:
                end = matching_brace(code, i)
                if is_function_body(header):
                    first = header_start + len(header) - len(header.lstrip())
                    yield line_of[first], line_of[end], function_name(header)
                    header_start = end + 1
                i = end  # a brace initialiser: keep the header running
        i += 1


def matching_brace(code: str, start: int) -> int:
    depth = 0
    for k in range(start, len(code)):
        if code[k] == "{":
            depth += 1
        elif code[k] == "}":
            depth -= 1
            if depth == 0:
                return k
    return len(code) - 1


ACCESS = re.compile(r"^\s*(public|private|protected)\s*:(?!:)")
NOT_MEMBER = re.compile(r"^\s*(static|using|typedef|friend|template|static_assert|class|struct|union|enum)\b")
CLASS_NAME = re.compile(r"\b(class|struct|union)\s+(?:alignas\s*\([^)]*\)\s*)?([A-Za-z_][\w:]*)")


def top_level(text: str):
    """Yield (index, character) of the characters of text outside (), [], {} and <>."""
    depth = angle = 0
    for k, ch in enumerate(text):
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif depth == 0 and ch == "<":
            angle += 1
        elif depth == 0 and ch == ">" and angle > 0 and text[k - 1] != "-":
            angle -= 1
        elif depth == 0 and angle == 0:
            yield k, ch
        if ch in "([{" and depth == 1 and angle == 0:
            yield k, ch  # an opening bracket at top level


def count_declarators(statement: str) -> int:
    """Data members declared by one class-level statement (0 for functions and the like)."""
    while ACCESS.match(statement):
        statement = ACCESS.sub("", statement, count=1)
    statement = statement.strip()
    if not statement or NOT_MEMBER.match(statement):
        return 0
    if re.match(r"^(inline\s+)?(constexpr\s+)?static\b", statement) or "operator" in statement:
        return 0
    for _, ch in top_level(statement):
        if ch in "={":
            break
        if ch == "(":
            return 0  # a function declaration (or a function pointer)
    return 1 + sum(1 for _, ch in top_level(statement) if ch == ",")


def walk_classes(code: str, start: int, end: int, scope: str, in_class: bool, out: list, line_of):
    """Append (first line, qualified name, data members) of every class in code[start:end]."""
    header_start, i, members = start, start, 0
    pending_declarators = False  # after `struct X {...}` the declarators before `;` are members
    while i < end:
        c = code[i]
        if c == ";":
            statement = code[header_start:i]
            if pending_declarators:
                members += len([d for d in statement.split(",") if d.strip()])
                pending_declarators = False
            elif in_class:
                members += count_declarators(statement)
            header_start = i + 1
        elif c == "}":
            header_start = i + 1
        elif c == "{":
            header = code[header_start:i]
            close = matching_brace(code, i)
            stripped = ACCESS.sub("", header) if in_class else header
            while in_class and ACCESS.match(stripped):
                stripped = ACCESS.sub("", stripped, count=1)
            container = CONTAINER.match(stripped) and "(" not in stripped
            if container and re.search(r"\b(class|struct|union)\b", stripped) \
                    and not re.search(r"\benum\b", stripped):
                name = CLASS_NAME.search(stripped)
                name = name.group(2) if name else "<anonymous>"
                qualified = f"{scope}::{name}" if scope else name
                first = header_start + len(header) - len(header.lstrip())
                out.append([line_of[first], qualified, 0])
                entry = out[-1]
                entry[2] = walk_classes(code, i + 1, close, qualified, True, out, line_of)
                if in_class:
                    pending_declarators = True
                header_start = close + 1
            elif container and re.search(r"\bnamespace\b|extern", stripped):
                name = re.search(r"namespace\s+([\w:]+)", stripped)
                inner = f"{scope}::{name.group(1)}" if scope and name else (name.group(1) if name else scope)
                walk_classes(code, i + 1, close, inner, False, out, line_of)
                header_start = close + 1
            elif container:  # an enum
                header_start = close + 1
                if in_class:
                    pending_declarators = True
            elif is_function_body(header):
                header_start = close + 1
            i = close  # else a brace initialiser: the statement runs on to its `;`
        i += 1
    return members


def classes(text: str):
    """(first line, qualified name, non-static data members) of every class or struct in text."""
    code = blank(text)
    line_of = line_numbers(code)
    out = []
    walk_classes(code, 0, len(code), "", False, out, line_of)
    return [tuple(entry) for entry in out]


def source_files(paths):
    for path in paths:
        path = Path(path)
        files = sorted(path.rglob("*")) if path.is_dir() else [path]
        for f in files:
            if f.suffix in (".cc", ".h") and f.is_file():
                try:
                    shown = f.resolve().relative_to(ROOT)
                except ValueError:
                    shown = f
                yield f, shown


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("paths", nargs="*", default=[str(ROOT / "src")])
    parser.add_argument("--max-lines", type=int, default=120)
    parser.add_argument("--top", type=int, default=0, help="also list the K longest functions")
    parser.add_argument("--members", type=int, default=None, metavar="M",
                        help="list the classes with more than M data members instead")
    args = parser.parse_args()

    if args.members is not None:
        found = [(n, f"{shown}:{first}", name) for f, shown in source_files(args.paths)
                 for first, name, n in classes(f.read_text(errors="ignore"))]
        found.sort(key=lambda entry: (-entry[0], entry[1]))
        big = [entry for entry in found if entry[0] > args.members]
        for n, where, name in big:
            print(f"{n:5d}  {where}  {name}")
        print(f"{len(big)} of {len(found)} classes have more than {args.members} data members")
        return 0

    functions = []
    for f, shown in source_files(args.paths):
        for first, last, name in scan(f.read_text(errors="ignore")):
            functions.append((last - first + 1, f"{shown}:{first}", name))
    functions.sort(key=lambda entry: (-entry[0], entry[1]))
    long_ones = [entry for entry in functions if entry[0] > args.max_lines]
    for lines, where, name in long_ones:
        print(f"{lines:5d}  {where}  {name}")
    print(f"{len(long_ones)} of {len(functions)} functions are longer than {args.max_lines} lines")
    if args.top:
        print(f"the {args.top} longest:")
        for lines, where, name in functions[:args.top]:
            print(f"{lines:5d}  {where}  {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
