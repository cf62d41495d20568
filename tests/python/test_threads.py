"""Device work releases the GIL: another Python thread runs while a view renders and while a
trainer steps (were the GIL held, the counting thread would stand still until they return)."""
import threading
import time

import numpy as np

import vknerf


def ticks_while(work):
    """How many times this thread ticks (every 0.5 ms) while `work` runs on another."""
    done = threading.Event()
    worker = threading.Thread(target=lambda: (work(), done.set()))
    ticks = 0
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.0005)
    worker.join()
    return ticks


def test_rendering_and_training_release_the_gil(ctx, synthetic):
    images, poses, k = synthetic
    trainer = vknerf.Trainer(ctx, vknerf.Dataset.from_arrays(images, poses, k),
                             vknerf.TrainConfig.vanilla(ctx, width=32, depth=2, coarse=8, fine=8, rays=256))
    trainer.step()
    model = trainer.model()
    big = dict(pose=poses[0], intrinsics=k * np.float32(16), width=256, height=192)
    model.render(**big)  # kernels compiled
    # Hundreds to thousands of ticks on two cores; with the GIL held there would be at most one
    # per step boundary.
    assert ticks_while(lambda: model.render(**big)) >= 50
    assert ticks_while(lambda: trainer.step(20)) >= 50
