"""Model.load with a default context, Model.render_dataset and vknerf.evaluate."""
from . import _vknerf

_load = _vknerf.Model.load


def load(path, context=None, march_steps=0, coarse_samples=0, fine_samples=0, appearance=None, profile=False):
    """A checkpoint written by Trainer.save or `vknerf train`; context None: vknerf.default_context().
    march_steps / coarse_samples / fine_samples: render settings (0: as trained). profile: each
    render's kernels timed on the device, in its dict's kernel_ms ({name: ms}; empty where the
    device's queue has no timestamps)."""
    if context is None:
        from . import default_context

        context = default_context()
    return _load(path, context, march_steps, coarse_samples, fine_samples, appearance, profile)


def render_dataset(self, dataset):
    """Renders each of the dataset's cameras in turn: yields render() dicts."""
    for camera in dataset.cameras:
        yield self.render(camera)


def evaluate(model, dataset):
    """PSNR and SSIM of each of the dataset's views against its photo (composited over the model's
    background), as `vknerf eval` computes them: a dict of names, psnr and ssim (arrays, one per
    view), mean_psnr and mean_ssim."""
    return _vknerf._evaluate(model, dataset)


_vknerf.Model.load = staticmethod(load)
_vknerf.Model.render_dataset = render_dataset
