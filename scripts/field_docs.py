#!/usr/bin/env python3
"""The docstrings of the Python module's fields, from the C++ headers' member comments.

A config, input or output field is documented once, where it is declared, in its header:

    double dt = 0.001;                  // [s] control period
    // [m] trunk origin above the ground, along world z. 0: derived so that ...
    double stand_height = 0.0;

The build (cmake/field_docs.cmake) runs this script over cpp/include/kiloloop and bindings/*.cpp
and writes a C++ table {python class, field, doc} that bindings/field_docs.cpp attaches to the
module's properties at import, so `help(kl.QuadrupedConfig.dt)`, an IDE and the .pyi stubs
(cmake/stubs.cmake) show the header's text. Which C++ member a Python field is: the binding's
member pointer (`.def_readwrite("dt", &QuadrupedConfig::dt)`, `vector_field(in, "q",
&JointControlInput::q, ...)`), in the py::class_ it is bound on (the nearest `py::class_<...>`
above it in the source).

    python scripts/field_docs.py INCLUDE_DIR BINDINGS_DIR OUT.inc
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

CLASS_DECL = re.compile(r"^\s*(?:struct|class)\s+(\w+)\s*(?:final\s*)?(?::[^{;]*)?\{\s*$")
# A data member: type, name, optional initializer ({...} or = ...), ';', optional // comment.
MEMBER = re.compile(r"^\s*(?!return\b|using\b|friend\b|static\b|typedef\b)[\w:<>,\s\*&]+?[\s\*&>](\w+)"
                    r"\s*(?:\{[^;]*\}|=[^;]*)?;\s*(?://\s?(.*))?$")
BIND_CLASS = re.compile(r"py::class_<\s*([\w:]+)[^>]*>\s*(?:\w+\s*)?\(\s*\w+\s*,\s*\"(\w+)\"")
BIND_FIELD = re.compile(r"\"(\w+)\"\s*,\s*&([\w:]+)::(\w+)\s*[,)]")
# A binding template's instantiation: bind_joint_config<ComputedTorqueConfig>(m, "ComputedTorqueConfig");
# its fields name the template parameter (&Config::kp): each argument is tried as that struct.
BIND_TEMPLATE_CALL = re.compile(r"\b(?!class_\b)\w+<\s*([\w:]+(?:\s*,\s*[\w:]+)*)\s*>\(\s*\w+\s*,\s*\"(\w+)\"")


def member_docs(include_dir: Path) -> dict[tuple[str, str], str]:
    """(struct, member) -> its comment: the trailing one, else the comment lines right above."""
    docs: dict[tuple[str, str], str] = {}
    for header in sorted(include_dir.rglob("*.hpp")):
        _scan(header.read_text().splitlines(), docs)
    return docs


def _scan(lines: list[str], docs: dict[tuple[str, str], str]) -> None:
    stack: list[tuple[str, int]] = []   # (struct name, brace depth of its body)
    depth, above, statement = 0, [], ""
    for line in lines:
        code = line.split("//", 1)[0]
        comment = line.split("//", 1)[1].strip() if "//" in line else ""
        opened = CLASS_DECL.match(line)
        if opened:
            stack.append((opened.group(1), depth + 1))
            above, statement = [], ""
        elif stack and (depth == stack[-1][1] or statement):  # a member, or its next line
            if not code.strip():
                above = above + [comment] if comment else []
            else:
                statement += " " + code.strip()
                if statement.rstrip().endswith(";") and "(" not in statement.split("=")[0] \
                        .split("{")[0]:
                    m = MEMBER.match(statement.strip() + (f" // {comment}" if comment else ""))
                    doc = (m.group(2) or "").strip() if m else ""
                    if m and not doc and above:
                        doc = " ".join(above)
                    if m and doc:
                        for name in _declarators(statement, m.group(1)):
                            docs.setdefault((stack[-1][0], name), doc)
                if statement.rstrip().endswith((";", "}", "{")) or code.strip().endswith(":"):
                    statement, above = "", []
        depth += code.count("{") - code.count("}")
        while stack and depth < stack[-1][1]:
            stack.pop()
            above, statement = [], ""


def _declarators(statement: str, last: str) -> list[str]:
    """The names a member declaration declares: `Eigen::VectorXd lower, upper;` -> both."""
    several = re.match(r"^\s*[\w:<>\s\*&]+?\s(\w+(?:\s*,\s*\w+)+)\s*;\s*$", statement)
    return [n.strip() for n in several.group(1).split(",")] if several else [last]


def field_docs(include_dir: Path, bindings_dir: Path) -> list[tuple[str, str, str]]:
    """(python class, python field, doc) for every bound member whose header comments it."""
    docs = member_docs(include_dir)
    structs = {struct for struct, _ in docs}
    out: dict[tuple[str, str], str] = {}
    for source in sorted(bindings_dir.glob("*.cpp")):
        text = source.read_text()
        classes = [(m.start(), m.group(2)) for m in BIND_CLASS.finditer(text)]
        instances = [([a.strip().split("::")[-1] for a in m.group(1).split(",")], m.group(2))
                     for m in BIND_TEMPLATE_CALL.finditer(text)]
        for m in BIND_FIELD.finditer(text):
            struct, member = m.group(2).split("::")[-1], m.group(3)
            if struct in structs:                    # a header's struct: bound on the class above
                owner = [name for pos, name in classes if pos < m.start()]
                doc = docs.get((struct, member))
                if owner and doc:
                    out.setdefault((owner[-1], m.group(1)), doc)
                continue
            for args, py_name in instances:          # a template parameter: its instantiations
                doc = next((docs[(a, member)] for a in args if (a, member) in docs), None)
                if doc:
                    out.setdefault((py_name, m.group(1)), doc)
    return [(c, f, d) for (c, f), d in sorted(out.items())]


def _cpp_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def main(argv: list[str]) -> int:
    include_dir, bindings_dir, out = map(Path, argv[1:4])
    rows = field_docs(include_dir, bindings_dir)
    text = "// Generated by scripts/field_docs.py: {python class, field, doc}. Do not edit.\n" + "".join(
        f"{{{_cpp_string(c)}, {_cpp_string(f)}, {_cpp_string(d)}}},\n" for c, f, d in rows)
    # Written every time: a file left older than its inputs would stay out of date for Ninja,
    # which would run this again and rebuild the module's bindings at every build.
    out.write_text(text)
    print(f"field_docs: {len(rows)} documented fields -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
