pytest_plugins = ["pytester"]  # the pytest plugin's fixture test (tests/test_scenario_files.py)

from pathlib import Path

import numpy as np
import pytest

import kiloloop as kl

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def ur5_urdf():
    return kl.models_dir() / "ur5" / "ur5.urdf"


@pytest.fixture(scope="session")
def ur5_model(ur5_urdf):
    return kl.RobotModel.from_urdf(str(ur5_urdf))


@pytest.fixture
def rng(request):
    seed = 20261122
    print(f"seed {seed} for {request.node.name}")
    return np.random.default_rng(seed)


@pytest.fixture(scope="session")
def firmware_prefix():
    """Install prefix of the firmware path's core (kiloloop_core compiled with -fno-exceptions
    -fno-rtti, the URDF loader beside it), built once per session in the source tree's
    build/firmware (incremental across sessions). The back-to-back tests and the embed example
    both build against it through find_package(kiloloop): one core compile (about 3 minutes on 2
    cores from clean) where each used to compile its own."""
    from kiloloop.firmware import build
    return build.install_rt_core(ROOT, ROOT / "build" / "firmware")


def pytest_collection_modifyitems(session, config, items):
    """The processor-in-the-loop tests (tests/test_pil_*.py) run last: `make test` builds their
    cross-compiled cores in the background meanwhile (scripts/run_tests.sh), and a PIL test that
    comes before its core is built waits for it."""
    items.sort(key=lambda item: Path(str(item.fspath)).name.startswith("test_pil_"))
