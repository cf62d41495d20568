"""Ctrl-C stops Trainer.train at the next step boundary and leaves a checkpoint that loads: from a
signal raised in the callback, and from SIGINT sent to a process while it trains (the step runs
with the GIL released; the signal is seen between steps)."""
import os
import signal
import subprocess
import sys
import textwrap

import pytest

import vknerf
from helpers import FAST_FIELDS, SCENE


def test_signal_from_the_callback_stops_and_saves(ctx, quarter_scene, tmp_path):
    path = str(tmp_path / "stopped.vknerf")
    trainer = vknerf.Trainer(ctx, quarter_scene, vknerf.TrainConfig.fast(ctx, **FAST_FIELDS))

    def stop_at_step_6(stats):
        if stats["step"] == 6:
            signal.raise_signal(signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        trainer.train(steps=1000, log_every=3, callback=stop_at_step_6, checkpoint=path, progress=False)
    # train runs its steps two deep: step 6's statistics arrive once step 7 is submitted, and the
    # signal stops the loop before step 8. The trainer stops there, step 7 finished.
    assert trainer.steps == 7
    assert vknerf.Trainer.config_of(path).as_dict()["seed"] == FAST_FIELDS["seed"]
    view = vknerf.Model.load(path, ctx).render(quarter_scene.cameras[0])
    assert view["rgb"].shape == (25, 25, 3)
    trainer.step()  # the trainer goes on where it stopped
    assert trainer.steps == 8


def test_sigint_to_a_training_process(tmp_path):
    path = str(tmp_path / "sigint.vknerf")
    script = textwrap.dedent(f"""
        import sys, vknerf
        data = vknerf.Dataset.load({SCENE!r}, downscale=4)
        trainer = vknerf.Trainer(vknerf.Context(), data, vknerf.TrainConfig.fast(**{FAST_FIELDS!r}))
        def report(stats):
            print("step", stats["step"], flush=True)
        try:
            trainer.train(steps=100000, log_every=2, callback=report, checkpoint={path!r}, progress=False)
        except KeyboardInterrupt:
            print("interrupted at", trainer.steps, flush=True)
            sys.exit(130)
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, env=os.environ.copy())
    try:
        assert p.stdout.readline().startswith("step 2")
        p.send_signal(signal.SIGINT)
        out = p.stdout.read()
        assert p.wait(timeout=60) == 130, out
    finally:
        p.kill()
    stopped = int(out.strip().splitlines()[-1].split()[-1])
    assert stopped >= 2
    assert vknerf.Trainer.config_of(path).model == "fast"
    vknerf.Model.load(path)
