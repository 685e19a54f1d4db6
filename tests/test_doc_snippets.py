"""Every fenced code block of README.md and docs/*.md runs, verbatim, or is checked as what it is.

The rules (docs/hardening.md, "The docs' code blocks", says the same to a doc's author):
- ```python: run as written in a fresh interpreter (this one), cwd the doc's scratch directory;
  it must exit 0.
- ```sh, ```bash, ```shell, ```console: the block runs as written as one bash script with `set -e`
  (a console block: its `$ ` lines) in the doc's scratch directory; `kiloloop` and `python` are
  this interpreter's. It must exit 0.
- ```toml: parsed with tomllib.
- no language, or ```text: output, trees, diagrams; not run. A line in it that starts with
  `kiloloop ` is a command synopsis: its subcommand, every `--option` it names and the scenario it
  names (lower case, not a placeholder) must exist.
- any other language (cpp, cmake, ...): must be marked skip (it is compiled by the tests that
  build the examples, or it is a sketch).
Markers, an HTML comment on the line right above the fence:
- `<!-- snippet: skip (reason) -->`: not run (a toml block is still parsed, a synopsis still
  checked); the reason, in the doc for its reader, is required. Expensive commands (builds, apt,
  sweeps over many runs, video, benchmarks, scenarios without a file of their own) are skipped so.
- `<!-- snippet: file NAME -->`: the block's text is the file NAME; it is written into the doc's
  scratch directory before that doc's blocks run.
Each doc gets one fresh scratch directory in which `models` links to the repository's models/, so
commands written for the repository root (`models/ur5/robot.toml`) run as written.
"""
from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
import textwrap
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest

import kiloloop

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
RUN_LANGS = {"python", "sh", "bash", "shell", "console"}
TEXT_LANGS = {"", "text"}
MARKER = re.compile(r"^<!--\s*snippet:\s*(\w+)\s*(.*?)\s*-->$")
FENCE = re.compile(r"^(\s*)(```+)\s*([\w+-]*)\s*(.*)$")
TIMEOUT = 120  # [s] per block: a hung block fails instead of holding the suite


@dataclass
class Block:
    doc: Path
    line: int          # 1-based line of the opening fence
    lang: str
    text: str
    marker: str = ""   # "skip" | "file" | ""
    argument: str = ""  # the skip's reason, the file's name

    @property
    def id(self) -> str:
        return f"{self.doc.name}:{self.line}-{self.lang or 'text'}"


def blocks_of(doc: Path) -> list[Block]:
    """The fenced blocks of a markdown file with the marker right above each."""
    lines = doc.read_text().splitlines()
    out, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence, lang = m.group(1), m.group(2), m.group(3).lower()
        start, body = i, []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        i += 1
        block = Block(doc, start + 1, lang, "\n".join(body) + "\n")
        above = lines[start - 1].strip() if start > 0 else ""
        marker = MARKER.match(above)
        if marker:
            block.marker = marker.group(1)
            block.argument = marker.group(2).strip()
            if block.marker == "skip":
                block.argument = block.argument.removeprefix("(").removesuffix(")").strip()
        out.append(block)
    return out


ALL = [b for doc in DOCS for b in blocks_of(doc)]


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    """One scratch directory per doc (models/ linked, the doc's file blocks written), and an
    environment whose `kiloloop` and `python` are this interpreter with this kiloloop."""
    shims = tmp_path_factory.mktemp("bin")
    for name, command in (("kiloloop", f"{shlex.quote(sys.executable)} -m kiloloop.cli"),
                          ("python", shlex.quote(sys.executable))):
        path = shims / name
        path.write_text(f'#!/bin/sh\nexec {command} "$@"\n')
        path.chmod(0o755)
    env = dict(os.environ)
    env["PATH"] = f"{shims}{os.pathsep}{env.get('PATH', '')}"
    package_root = str(Path(kiloloop.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join([package_root] + [p for p in
                                         env.get("PYTHONPATH", "").split(os.pathsep) if p])
    env.setdefault("MPLBACKEND", "Agg")
    dirs = {}

    def get(doc: Path) -> Path:
        if doc not in dirs:
            d = tmp_path_factory.mktemp(doc.stem)
            (d / "models").symlink_to(ROOT / "models", target_is_directory=True)
            for b in blocks_of(doc):
                if b.marker == "file":
                    (d / b.argument).parent.mkdir(parents=True, exist_ok=True)
                    (d / b.argument).write_text(b.text)
            dirs[doc] = d
        return dirs[doc]

    get.env = env
    return get


def _run(args, cwd, env, what: str):
    r = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=TIMEOUT)
    assert r.returncode == 0, (f"{what} exited {r.returncode}\n--- stdout\n{r.stdout[-3000:]}"
                               f"\n--- stderr\n{r.stderr[-3000:]}")
    return r


def console_commands(text: str) -> str:
    """The commands of a console block: its `$ ` lines (and their `> ` continuations)."""
    out = []
    for line in text.splitlines():
        if line.startswith("$ "):
            out.append(line[2:])
        elif line.startswith("> ") and out:
            out.append(line[2:])
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("block", ALL, ids=[b.id for b in ALL])
def test_block(block: Block, scratch, cli_help):
    assert block.marker in ("", "skip", "file"), (
        f"{block.id}: unknown marker {block.marker!r} (skip or file)")
    if block.marker == "skip":
        assert block.argument, f"{block.id}: a skip needs its reason: <!-- snippet: skip (why) -->"
    if block.marker == "file":
        assert block.argument and not Path(block.argument).is_absolute() \
            and ".." not in Path(block.argument).parts, f"{block.id}: file NAME, relative"
    if block.lang == "toml":
        tomllib.loads(block.text)
        return
    if block.lang in TEXT_LANGS:
        check_synopsis(block, cli_help)
        return
    if block.lang not in RUN_LANGS:
        assert block.marker == "skip", (
            f"{block.id}: a ```{block.lang} block is neither run nor parsed here: mark it "
            "<!-- snippet: skip (reason) --> (say which test builds it, or that it is a sketch)")
        return
    if block.marker == "skip":
        pytest.skip(f"{block.id}: {block.argument}")
    cwd = scratch(block.doc)
    if block.lang == "python":
        _run([sys.executable, "-c", block.text], cwd, scratch.env, block.id)
    else:
        script = console_commands(block.text) if block.lang == "console" else block.text
        assert script.strip(), f"{block.id}: no command in it"
        _run(["bash", "-e", "-x", "-c", script], cwd, scratch.env, block.id)


# -- command synopses (text blocks) --------------------------------------------------------------

_HELP_SCRIPT = textwrap.dedent("""
    import contextlib, io, json, sys
    from kiloloop.cli import main
    out = {}
    for path in json.loads(sys.argv[1]):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(io.StringIO()):
            try:
                main(path + ["--help"])
            except SystemExit:
                pass
        out[" ".join(path)] = buf.getvalue()
    with contextlib.redirect_stdout(io.StringIO()) as buf:
        main(["list"])
    out["\\0scenarios"] = buf.getvalue()
    print(json.dumps(out))
""")


@pytest.fixture(scope="module")
def cli_help(scratch):
    """Every `kiloloop ... --help` text by command path ("", "run", "robot check", ...) and
    `kiloloop list` under "\0scenarios": asked level by level, one interpreter per level."""
    helps: dict[str, str] = {}
    level: list[list[str]] = [[]]
    while level:
        r = subprocess.run([sys.executable, "-c", _HELP_SCRIPT, json.dumps(level)],
                           env=scratch.env, capture_output=True, text=True, timeout=TIMEOUT)
        assert r.returncode == 0, r.stderr
        got = json.loads(r.stdout)
        helps.update(got)
        level = [p + [sub] for p in level for sub in sorted(_subcommands(got[" ".join(p)]))]
    return helps


def synopsis_commands(text: str) -> list[str]:
    """`kiloloop ...` lines of a text block, each with its indented continuation lines."""
    commands = []
    for line in text.splitlines():
        if re.match(r"kiloloop [a-z][\w-]*(\s|$)", line):  # not `kiloloop run: ...` (a message)
            commands.append(re.split(r"\s{2,}", line)[0])  # before its comment or description
        elif commands and line.startswith(" ") and line.strip().startswith("["):
            commands[-1] += " " + line.strip()
    return commands


def _subcommands(help_text: str) -> set[str]:
    m = re.search(r"^  \{([\w,-]+)\}$", help_text, re.M)  # argparse's line of subcommands
    return set(m.group(1).split(",")) if m else set()


def check_synopsis(block: Block, helps: dict[str, str]) -> None:
    """Each `kiloloop ...` line: its subcommand path, options and scenario exist."""
    scenarios = {line.split()[0] for line in helps["\0scenarios"].splitlines() if line.strip()}
    for command in synopsis_commands(block.text):
        words = command.split()[1:]
        path: list[str] = []
        while words and words[0] in _subcommands(helps[" ".join(path)]):
            path.append(words.pop(0))
        assert path, f"{block.id}: {command!r}: no such subcommand"
        text = helps[" ".join(path)]
        for option in re.findall(r"(?<![\w-])(--[a-z][\w-]*)", command):
            assert re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", text), (
                f"{block.id}: {command!r}: `kiloloop {' '.join(path)}` has no {option}")
        if path[0] in ("run", "sweep") and words and re.fullmatch(r"[a-z][a-z0-9-]*", words[0]):
            assert words[0] in scenarios, f"{block.id}: {command!r}: no scenario {words[0]!r}"


# -- the README's batch example: its rollouts start at the plant's state and track ---------------

def test_readme_batch_example_tracks(scratch):
    """The README's batch example, verbatim, then its logs judged: every rollout ran to the end
    without a MuJoCo warning, tracked within 2 mrad (noise 0.1 mrad included; a rollout started at
    qpos0 instead of the start pose read 2.28 rad and pinned 150 N m) and never saturated."""
    [block] = [b for b in ALL if b.doc.name == "README.md" and b.lang == "python"
               and "batch.run(" in b.text]
    check = textwrap.dedent("""
        import json
        import numpy as np
        effort = np.asarray(rig.model.effort_limit)
        print(json.dumps([{"ok": bool(r.ok), "ticks": int(r.ticks_run),
                           "warnings": int(r.warnings),
                           "error": float(np.abs(lg["q"] - lg["q_ref"]).max()),
                           "tau_over_effort": float((np.abs(lg["tau"]) / effort).max()),
                           "statuses": sorted({int(s) for s in lg["status"]})}
                          for r, lg in zip(rollouts, logs)]))
    """)
    r = _run([sys.executable, "-c", block.text + check], scratch(block.doc), scratch.env, block.id)
    runs = json.loads(r.stdout.strip().splitlines()[-1])
    print(runs)
    assert len(runs) >= 2
    for run in runs:
        assert run["ok"] and run["ticks"] == 2000 and run["warnings"] == 0, run
        assert run["error"] < 2e-3, run
        assert run["tau_over_effort"] < 0.9 and run["statuses"] == [0], run


# -- docs/DESIGN.md's layout names what is there ---------------------------------------------------

def _layout_block() -> Block:
    design = ROOT / "docs" / "DESIGN.md"
    text = design.read_text()
    heading = text.index("## Layout")
    return next(b for b in blocks_of(design)
                if text.count("\n", 0, heading) < b.line and b.lang in TEXT_LANGS)


def _layout_paths(block: Block) -> list[str]:
    """Paths the layout names: a top-level line's first word; on a line indented by two spaces,
    the words before its description (two spaces) that end in `/` or have a file suffix, under the
    last top-level directory (deeper indentation continues a description). `<robot>` stands for every robot directory, `...` for anything."""
    paths, parent = [], ""
    for line in block.text.splitlines():
        if not line.strip() or line.startswith("   "):  # a description's continuation line
            continue
        if not line.startswith(" "):
            names = line.split()[:1]
        else:
            names = [w for w in line.strip().split("  ")[0].split()
                     if w.endswith("/") or re.search(r"\w\.\w+$", w)]
        for name in names:
            name = name.replace("<robot>", "ur5").removesuffix("...").rstrip("/")
            paths.append(f"{parent}/{name}" if line.startswith(" ") else name)
        if not line.startswith(" ") and names[0].endswith("/"):
            parent = names[0].rstrip("/")
    return paths


def test_design_layout_is_the_tree():
    """Every path docs/DESIGN.md's layout names exists, and it names every top-level directory
    and every directory of cpp/include/kiloloop/, cpp/ and python/kiloloop/."""
    block = _layout_block()
    named = _layout_paths(block)
    missing = [p for p in named if not (ROOT / p).exists()]
    assert not missing, f"DESIGN.md's layout names paths that do not exist: {missing}"
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
    if tracked.returncode != 0:
        pytest.skip("not a git checkout")
    files = tracked.stdout.split()
    dirs = set()
    for f in files:
        parts = f.split("/")
        if len(parts) > 1 and not parts[0].startswith("."):
            dirs.add(parts[0])
        for prefix in ("cpp/include/kiloloop/", "cpp/", "python/kiloloop/"):
            rest = f[len(prefix):].split("/") if f.startswith(prefix) else []
            if len(rest) > 1 and not rest[0].startswith("_"):
                dirs.add(prefix + rest[0])
    named_set = {"/".join(p.split("/")[:i + 1]) for p in named for i in range(p.count("/") + 1)}
    unnamed = sorted(d for d in dirs if d not in named_set)
    assert not unnamed, f"DESIGN.md's layout does not name: {unnamed}"
