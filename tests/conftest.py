import numpy as np
import pytest

import kiloloop as kl


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
