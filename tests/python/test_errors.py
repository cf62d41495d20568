"""Bad arguments raise vknerf.Error subclasses that are also Python's own (ValueError, OSError),
with vknerf's one-line messages; configuration fields are checked as `vknerf train` checks its
flags, in the same words."""
import gc

import numpy as np
import pytest

import vknerf
from helpers import SCENE, run_cli


def cli_error(*flags):
    """The first line `vknerf train` prints on stderr for these flags (it fails before training)."""
    code, out, err = run_cli("train", SCENE, "--steps", "1", "-o", "unwritten.vknerf", *flags)
    assert code != 0, out
    return err.strip().splitlines()[0]


@pytest.mark.parametrize("fields, flags", [
    ({"width": 4}, ["--width", "4"]),
    ({"cone_angle": -1.0}, ["--cone-angle", "-1.0"]),  # the value as Python writes it
    ({"far_field": "painted"}, ["--far-field", "painted"]),
])
def test_config_fields_fail_as_the_cli_flags_do(fields, flags):
    with pytest.raises(vknerf.InvalidArgumentError) as e:
        vknerf.TrainConfig.fast(**fields)
    assert str(e.value) == cli_error("--config", "fast", *flags)


def test_config_fields_set_what_the_flags_set():
    c = vknerf.TrainConfig.fast(width=32, cone_angle=0.004, seed=7, refine_cameras=True, far_field="constant")
    d = c.as_dict()
    assert (d["model.width"], d["seed"], d["refine_cameras"], d["model.far_field"]) == (32, 7, True, "constant")
    assert d["model.cone_angle"] == pytest.approx(0.004)
    assert c.model == "fast" and vknerf.TrainConfig.vanilla(coarse=16).as_dict()["model.coarse_samples"] == 16
    assert c.replace(seed=9).as_dict()["seed"] == 9 and c.as_dict()["seed"] == 7
    assert "cone_angle" in vknerf.TrainConfig.names()


def test_unknown_and_other_models_fields():
    with pytest.raises(ValueError, match="unknown configuration field 'cone'; the fields: rays, width"):
        vknerf.TrainConfig.fast(cone=1)
    with pytest.raises(ValueError, match=r"coarse \(--coarse\) applies to the vanilla model, not TrainConfig.fast"):
        vknerf.TrainConfig.fast(coarse=16)
    with pytest.raises(ValueError, match="--width: 3.5 is not an integer"):
        vknerf.TrainConfig.fast(width=3.5)
    with pytest.raises(ValueError, match="the configuration from these fields is invalid: model.width must be"):
        vknerf.TrainConfig.fast(width=36)  # in the flag's range, but not a multiple of 8


def test_missing_files_are_os_errors(ctx, tmp_path):
    with pytest.raises(vknerf.FileError) as e:
        vknerf.Dataset.load(str(tmp_path / "nowhere"))
    assert isinstance(e.value, OSError) and "nowhere" in str(e.value)
    with pytest.raises(OSError, match="missing.vknerf"):
        vknerf.Model.load(str(tmp_path / "missing.vknerf"))
    (tmp_path / "broken.vknerf").write_text("not a checkpoint")
    with pytest.raises(vknerf.Error) as e:
        vknerf.Model.load(str(tmp_path / "broken.vknerf"))
    assert not isinstance(e.value, OSError)  # the file is there: its contents are wrong
    with pytest.raises(vknerf.Error, match="split must be train, val, test or all, got 'dev'"):
        vknerf.Dataset.load(SCENE, split="dev")


def test_bad_train_and_render_arguments(ctx, synthetic, tmp_path):
    images, poses, k = synthetic
    data = vknerf.Dataset.from_arrays(images, poses, k)
    trainer = vknerf.Trainer(ctx, data, vknerf.TrainConfig.vanilla(width=32, depth=2, coarse=8, fine=8, rays=256))
    with pytest.raises(ValueError, match="train needs steps > 0 or time > 0"):
        trainer.train()
    with pytest.raises(OSError):
        trainer.save(str(tmp_path / "no" / "such" / "folder" / "m.vknerf"))
    model = trainer.model()
    with pytest.raises(ValueError, match="render needs a camera, or pose, intrinsics, width and height"):
        model.render(pose=poses[0])
    with pytest.raises(ValueError, match=r"pose must have shape \(4, 4\), got \(3, 4\)"):
        model.render(pose=poses[0][:3], intrinsics=k, width=8, height=8)
    with pytest.raises(ValueError, match="not both"):
        model.render(data.cameras[0], pose=poses[0])
    with pytest.raises(TypeError):
        vknerf.Trainer(ctx, "not a dataset", vknerf.TrainConfig.vanilla())


def test_a_model_outlives_its_trainer_and_a_trainer_its_context(synthetic):
    images, poses, k = synthetic
    context = vknerf.Context()
    trainer = vknerf.Trainer(context, vknerf.Dataset.from_arrays(images, poses, k),
                             vknerf.TrainConfig.vanilla(context, width=32, depth=2, coarse=8, fine=8, rays=256))
    del context
    gc.collect()
    trainer.step(2)
    model = trainer.model()
    del trainer
    gc.collect()
    view = model.render(pose=poses[1], intrinsics=k, width=16, height=12)
    assert view["rgb"].shape == (12, 16, 3) and np.isfinite(view["rgb"]).all()
    vertices, faces, colours = model.mesh(resolution=8, threshold=0.0, occupied_only=False)
    assert vertices.shape[1:] == (3,) and faces.shape[1:] == (3,) and colours.shape == vertices.shape
    assert vertices.dtype == np.float32 and faces.dtype == np.uint32 and colours.dtype == np.uint8
