"""A thousand small renders keep the process's memory flat: each view's arrays own their buffers
and are freed with them, on the Python side (tracemalloc) and the native one (RSS)."""
import gc
import tracemalloc

import numpy as np

import vknerf


def rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS")


def test_no_leak_over_1000_renders(ctx, synthetic):
    images, poses, k = synthetic
    data = vknerf.Dataset.from_arrays(images, poses, k)
    trainer = vknerf.Trainer(ctx, data, vknerf.TrainConfig.vanilla(ctx, width=32, depth=2, coarse=8, fine=8, rays=256))
    trainer.step()
    model = trainer.model()
    small = dict(pose=poses[0], intrinsics=k / np.float32(2), width=8, height=6)
    for _ in range(100):  # warm: kernels compiled, scratch buffers sized
        model.render(**small)
    gc.collect()
    tracemalloc.start()
    rss_before = rss_kib()
    py_before = tracemalloc.get_traced_memory()[0]
    total = 0.0
    for _ in range(1000):
        view = model.render(**small)
        total += float(view["rgb"][0, 0, 0])
    del view
    gc.collect()
    py_growth = tracemalloc.get_traced_memory()[0] - py_before
    rss_growth = rss_kib() - rss_before
    tracemalloc.stop()
    assert np.isfinite(total)
    # A leaked view would be >= 8 * 6 * 5 floats = 960 bytes each: ~1 MB over the loop.
    assert py_growth < 64 * 1024, py_growth
    assert rss_growth < 1024, f"RSS grew {rss_growth} KiB over 1000 renders"
