"""vknerf: NeRF training and rendering on Vulkan compute, with NumPy arrays in and out.

    import vknerf
    ctx = vknerf.Context()
    data = vknerf.Dataset.load("assets/tabletop", downscale=2)
    trainer = vknerf.Trainer(ctx, data, vknerf.TrainConfig.fast(ctx))
    trainer.train(steps=2000)
    view = trainer.model().render(vknerf.Dataset.load("assets/tabletop", split="test").cameras[0])
    view["rgb"]  # (H, W, 3) float32

Every vknerf failure raises vknerf.Error (InvalidArgumentError is also a ValueError, FileError an
OSError, OutOfMemoryError a MemoryError) with vknerf's one-line message.
"""
from ._vknerf import (  # noqa: F401
    Camera,
    Context,
    Dataset,
    Error,
    FileError,
    InvalidArgumentError,
    Model,
    OutOfMemoryError,
    Trainer,
    TrainConfig,
    devices,
)
from . import _model, _training  # noqa: F401  (they add Trainer.train, Model.render_dataset, ...)
from ._model import evaluate  # noqa: F401

_default_context = None


def default_context():
    """The context TrainConfig.fast() / .vanilla() and Model.load() use when given none: created on
    first use (the device VKNERF_DEVICE names, else the best), then shared."""
    global _default_context
    if _default_context is None:
        _default_context = Context()
    return _default_context
