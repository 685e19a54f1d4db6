"""The typed API (issue 32): the installed package carries py.typed and the .pyi stubs of _core
(cmake/stubs.cmake generates them from the built module), and `mypy --strict` passes on the
README's Python blocks against them.

One mypy run (about 12 s cold on the 2-core machine), its cache in the test's tmp dir. The run
also checks a probe with two deliberate errors that only the stubs can see: without them,
kiloloop._core would be Any and the README blocks would pass vacuously.

What has no type information yet, and is allowed here rather than in the README:
- mujoco ships no stubs nor py.typed (ignore_missing_imports);
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from importlib.util import find_spec
from pathlib import Path

import pytest

import kiloloop
from test_doc_snippets import ROOT, blocks_of

PACKAGE = Path(kiloloop.__file__).resolve().parent
STUBS = PACKAGE / "_core"

MYPY_INI = """\
[mypy]
strict = True

[mypy-mujoco.*]
ignore_missing_imports = True
"""

# Lines of the probe and the error mypy must report on each (the stubs' types at work).
PROBE = textwrap.dedent("""\
    import kiloloop as kl
    dt: str = kl.QuadrupedConfig().dt
    kl.RobotModel.from_urdf(1.5)
    """)
PROBE_ERRORS = {
    2: 'Incompatible types in assignment (expression has type "float", variable has type "str")',
    3: 'Argument 1 to "from_urdf" of "RobotModel" has incompatible type "float"; expected "str"',
}


def _need_stubs() -> None:
    if not (STUBS / "__init__.pyi").is_file():
        pytest.skip(f"no stubs in {STUBS} (built without pybind11-stubgen: cmake/stubs.cmake)")


def test_the_package_is_typed():
    _need_stubs()
    assert (PACKAGE / "py.typed").is_file()
    for sub in ("qp", "detmath", "native", "firmware"):
        assert (STUBS / f"{sub}.pyi").is_file(), sub
    text = (STUBS / "__init__.pyi").read_text()
    config = re.search(r"^class QuadrupedConfig:\n(.*?)^class ", text, re.S | re.M)
    assert config, "no class QuadrupedConfig in _core/__init__.pyi"
    field = r"^    (trunk_link: str|def trunk_link\(self\) -> str:)$"  # a field, or a property
    assert re.search(field, config.group(1), re.M)
    assert re.search(r"def dt\(self\) -> float:", config.group(1))
    assert "from . import qp" in text
    # Every documented field carries its header's member comment (scripts/field_docs.py): the
    # text an IDE shows. A binding's own doc stays in front of it.
    assert re.search(r'def dt\(self\) -> float:\n\s+"""\n\s+\[s\] control period', config.group(1))
    friction = re.search(r"^class JointFrictionConfig:\n(.*?)^class ", text, re.S | re.M)
    assert friction and re.search(r'def coulomb\(self\)[^\n]*:\n\s+"""\n\s+\(1 or nq\) \[N m\]',
                                  friction.group(1))


def test_every_config_field_has_a_docstring():
    """Each field of every *Config class of the module has a docstring (the header's comment
    or the binding's): a field added without one fails here, naming it."""
    import kiloloop._core as core
    missing = []
    for name in dir(core):
        cls = getattr(core, name)
        if not (isinstance(cls, type) and name.endswith("Config")):
            continue
        for field, value in vars(cls).items():
            if isinstance(value, property) and not (value.__doc__ or "").strip():
                missing.append(f"{name}.{field}")
    assert not missing, f"fields without a docstring: {missing}"


def test_mypy_strict_passes_on_the_readme(tmp_path):
    _need_stubs()
    if find_spec("mypy") is None:
        pytest.skip("mypy is not installed (the test extra has it)")
    files = []
    for block in blocks_of(ROOT / "README.md"):
        if block.lang == "python" and block.marker != "skip":
            files.append(tmp_path / f"readme_{block.line}.py")
            files[-1].write_text(block.text)
    assert len(files) >= 4
    (tmp_path / "probe.py").write_text(PROBE)
    (tmp_path / "mypy.ini").write_text(MYPY_INI)
    env = {k: v for k, v in os.environ.items() if k not in ("MYPYPATH", "MYPY_CACHE_DIR")}
    out = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--config-file", "mypy.ini",
         "--cache-dir", str(tmp_path / "cache"), "--no-color-output", "--no-error-summary",
         "--hide-error-context", *(f.name for f in files), "probe.py"],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
    errors = [line for line in out.stdout.splitlines() if ": error: " in line]
    readme = [e for e in errors if not e.startswith("probe.py:")]
    assert not readme, "mypy --strict on the README's blocks:\n" + "\n".join(readme)
    probe = {int(e.split(":")[1]): e.split(": error: ", 1)[1] for e in errors
             if e.startswith("probe.py:")}
    for line, message in PROBE_ERRORS.items():
        assert message in probe.get(line, ""), (
            f"the probe's line {line} should fail with {message!r} (are the stubs seen?): "
            f"{probe.get(line)!r}\n{out.stdout}{out.stderr}")
    assert set(probe) == set(PROBE_ERRORS), out.stdout
    assert out.returncode == 1, out.stdout + out.stderr  # the probe's errors, nothing worse
