"""The malformed-input corpus (tests/corpus/README.md) through the Python side: every robot file
and every URDF is refused with a ValueError (RobotFileError is one) whose message holds the words
of the file's `expect:` comment, and nothing crashes; the corpus's unbroken bases load."""
import re
from pathlib import Path

import pytest

import kiloloop as kl
from kiloloop.robot import Robot
from kiloloop import robot_check as check

CORPUS = Path(__file__).resolve().parent / "corpus"
URDFS = sorted((CORPUS / "urdf").glob("*.urdf"))
ROBOT_FILES = sorted((CORPUS / "robot").glob("*.toml"))


def expected_words(path: Path, default: str) -> list[str]:
    found = re.search(r"expect:(.*?)(?:-->|$)", path.read_text(), re.MULTILINE)
    words = found.group(1).split(";") if found else [default]
    return [w.strip().lower() for w in words if w.strip()]


def test_corpus_is_there():
    assert len(URDFS) >= 20 and len(ROBOT_FILES) >= 15


def test_bases_load():
    robot = Robot.load(CORPUS / "valid_arm.toml")
    lines = check.summary_lines(robot)
    assert robot.model().nq == 2 and lines
    assert kl.RobotModel.from_urdf(str(CORPUS / "valid_arm.urdf")).nq == 2


@pytest.mark.parametrize("path", URDFS, ids=lambda p: p.stem)
def test_malformed_urdf_is_refused_with_its_reason(path):
    with pytest.raises(ValueError) as err:
        kl.RobotModel.from_urdf(str(path))
    message = str(err.value).lower()
    for word in expected_words(path, "invalid urdf"):
        assert word in message, f"{path.name}: {word!r} not in {err.value}"


@pytest.mark.parametrize("path", ROBOT_FILES, ids=lambda p: p.stem)
def test_malformed_robot_file_is_refused_with_its_reason(path):
    # Loading validates the file; the summary loads the URDF, the model and the family's
    # controller settings (what `kiloloop robot check` does).
    with pytest.raises(ValueError) as err:
        check.summary_lines(Robot.load(path))
    message = str(err.value).lower()
    assert path.name.lower() in message, f"the error does not name the file: {err.value}"
    for word in expected_words(path, "missing key"):
        assert word in message, f"{path.name}: {word!r} not in {err.value}"
