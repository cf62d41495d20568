"""Shared fixtures: one context for the whole run (validation on under ctest, as for every test:
VKNERF_VALIDATION=1), the sample scene at a quarter size, a tiny synthetic dataset, and the
`vknerf` command line to compare with (VKNERF_CLI)."""
import os

import numpy as np
import pytest

import vknerf

from helpers import SCENE, look_at


@pytest.fixture(scope="session")
def ctx():
    context = vknerf.Context()
    # ctest runs this suite as every other test, with the layer required (VKNERF_VALIDATION=1).
    assert context.validation_enabled or os.environ.get("VKNERF_VALIDATION") != "1"
    vknerf._default_context = context  # the one TrainConfig.fast() and Model.load() use without one
    return context


@pytest.fixture(autouse=True)
def no_validation_messages(ctx):
    """Every test leaves the validation layer silent (it counts only when validation is on)."""
    before = ctx.validation_messages
    yield
    assert ctx.validation_messages == before, "validation-layer messages during the test"


@pytest.fixture(scope="session")
def quarter_scene(ctx):
    return vknerf.Dataset.load(SCENE, downscale=4)


@pytest.fixture(scope="session")
def quarter_test_scene(ctx):
    return vknerf.Dataset.load(SCENE, downscale=4, split="test")


@pytest.fixture(scope="session")
def synthetic():
    """Four 16x12 views of the origin with a deterministic pattern: images, poses, intrinsics."""
    n, h, w = 4, 12, 16
    y, x = np.mgrid[0:h, 0:w]
    images = np.stack([np.stack([(x * 37 + y * 11 + i * 53) % 256, (x * 7 + y * 29) % 256,
                                 (x * 3 + y * 5 + i * 101) % 256], -1) for i in range(n)]).astype(np.uint8)
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    poses = np.stack([look_at((3 * np.cos(a), 3 * np.sin(a), 1.0)) for a in angles])
    intrinsics = np.array([20.0, 20.0, w / 2, h / 2], np.float32)
    return images, poses, intrinsics
