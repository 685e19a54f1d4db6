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
    """Install prefix of the x86-64 firmware core: the installed wheel's kit (the very static
    libraries the Python module links: kiloloop_core compiled -fno-exceptions, the URDF loader
    beside it), else, run from a source tree without a wheel install, built once per session in
    the source tree's build/firmware (build.host_core). The back-to-back tests and the embed
    example build against it through find_package(kiloloop)."""
    from kiloloop.firmware import build
    return build.host_core(ROOT, ROOT / "build" / "firmware")


def pytest_collection_modifyitems(session, config, items):
    """The processor-in-the-loop tests (tests/test_pil_*.py) run last: `make test` builds their
    cross-compiled cores in the background meanwhile (scripts/run_tests.sh), and a PIL test that
    comes before its core is built waits for it."""
    items.sort(key=lambda item: Path(str(item.fspath)).name.startswith("test_pil_"))
