"""What the tests share besides fixtures: the scene, the command line, the flags both sides use."""
import os
import subprocess

import numpy as np
import pytest

SOURCE = os.environ.get("VKNERF_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SCENE = os.path.join(SOURCE, "assets", "tabletop")
CLI = os.environ.get("VKNERF_CLI")
# Small enough for a few seconds per run on two cores; the same settings for the CLI and Python.
# The tiny vanilla model trains deterministically; the fast model's hash-grid gradients are summed
# with float atomics in whatever order the device's threads reach them, so two runs of either
# front end agree to about 1e-7 dB, not bit for bit.
VANILLA_FIELDS = {"seed": 3, "width": 32, "depth": 2, "coarse": 8, "fine": 8, "rays": 256}
VANILLA_FLAGS = ["--seed", "3", "--width", "32", "--depth", "2", "--coarse", "8", "--fine", "8", "--rays", "256"]
FAST_FIELDS = {"seed": 3, "hash_log2_size": 14, "samples_per_step": 8192}
FAST_FLAGS = ["--seed", "3", "--hash-log2-size", "14", "--samples-per-step", "8192"]


def look_at(eye, target=(0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0)):
    """Camera-to-world in vknerf's convention: looking down -Z, +Y up."""
    eye, target, up = map(np.asarray, (eye, target, up))
    back = eye - target
    back = back / np.linalg.norm(back)
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    m = np.eye(4, dtype=np.float32)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, np.cross(back, right), back, eye
    return m


def run_cli(*args, cwd=None):
    """Runs `vknerf ARGS`; its exit code, stdout and stderr."""
    if not CLI:
        pytest.skip("VKNERF_CLI is not set (ctest sets it when the command line is built)")
    p = subprocess.run([CLI, *args], cwd=cwd, capture_output=True, text=True, timeout=240)
    return p.returncode, p.stdout, p.stderr
