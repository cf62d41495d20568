"""Trainer.train and Trainer.model, over the extension's Trainer._train loop (which runs
`vknerf train`'s schedule and checks for Ctrl-C between steps)."""
from . import _vknerf
from ._progress import Progress


def train(self, steps=0, time=0.0, callback=None, log_every=50, progress=None, checkpoint=None):
    """Trains for `steps` steps and/or `time` seconds (whichever ends first; compiling kernels is
    not counted), with the learning rates decaying over that budget as `vknerf train --steps/--time`
    does. Every `log_every` steps and at the last, `callback(stats)` gets a dict (step, loss, psnr,
    rays, samples, elapsed, fraction); returning False stops training there. `progress`: draw a
    progress line (None: when stderr is a terminal or in a notebook). `checkpoint`: a path saved to
    when training ends, however it ends (Ctrl-C's KeyboardInterrupt and a callback's exception are
    raised after the save). Returns a summary dict (steps, step, seconds, loss, psnr)."""
    bar = Progress()
    if progress is not None:
        bar.enabled = bool(progress)

    def report(stats):
        bar.update(stats)
        if callback is not None:
            return callback(stats)
        return None

    try:
        return self._train(int(steps), float(time), int(log_every), report, checkpoint)
    finally:
        bar.close()


def model(self):
    """The trainer's model as it stands (it changes as the trainer steps). It keeps the trainer's
    state alive, so it outlives this Trainer object."""
    return _vknerf.Model.of_trainer(self)


_vknerf.Trainer.train = train
_vknerf.Trainer.model = model
