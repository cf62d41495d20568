"""The same numbers from Python as from the command line on the same scene, settings and seed:
the training loss at step 50 (bit for bit for the deterministic vanilla model, to float atomics'
noise for the fast one), a rendered view bit for bit, the held-out metrics."""
import json

import numpy as np
import pytest

import vknerf
from helpers import FAST_FIELDS, FAST_FLAGS, SCENE, VANILLA_FIELDS, VANILLA_FLAGS, run_cli
from png import read_pfm, read_png

STEPS = 50


def cli_train(d, config, flags):
    return run_cli("train", SCENE, "--config", config, "--steps", str(STEPS), "--downscale", "4", "--log-every",
                   str(STEPS), "--summary", str(d / (config + ".json")), "-o", str(d / (config + ".vknerf")), *flags)


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    """`vknerf train` for 50 steps of each model, then `render` and `eval` of the vanilla one."""
    d = tmp_path_factory.mktemp("cli")
    model = str(d / "vanilla.vknerf")
    for config, flags in (("vanilla", VANILLA_FLAGS), ("fast", FAST_FLAGS)):
        code, out, err = cli_train(d, config, flags)
        assert code == 0, out + err
    code, out, err = run_cli("render", model, SCENE, "--downscale", "4", "--limit", "1", "-o", str(d / "renders"))
    assert code == 0, out + err
    code, out, err = run_cli("eval", model, SCENE, "--downscale", "4", "--limit", "3", "--json", str(d / "eval.json"))
    assert code == 0, out + err
    return {"model": model, "summary": json.load(open(d / "vanilla.json")), "fast": json.load(open(d / "fast.json")),
            "eval": json.load(open(d / "eval.json")),
            "rgb": read_png(str(d / "renders" / "rgb_0000.png")), "depth": read_pfm(str(d / "renders" / "depth_0000.pfm"))}


def train_50(ctx, data, config):
    trainer = vknerf.Trainer(ctx, data, config)
    reports = []
    summary = trainer.train(steps=STEPS, log_every=STEPS, callback=reports.append, progress=False)
    assert summary["step"] == STEPS and [r["step"] for r in reports] == [STEPS]
    assert reports[0]["loss"] == summary["loss"] and summary["loss"] > 0
    return summary


def test_loss_at_step_50_is_the_clis(ctx, quarter_scene, cli_run):
    summary = train_50(ctx, quarter_scene, vknerf.TrainConfig.vanilla(ctx, **VANILLA_FIELDS))
    assert summary["psnr"] == cli_run["summary"]["train_psnr"]  # bit for bit: the same doubles


def test_fast_loss_at_step_50_is_the_clis(ctx, quarter_scene, cli_run):
    summary = train_50(ctx, quarter_scene, vknerf.TrainConfig.fast(ctx, **FAST_FIELDS))
    assert summary["psnr"] == pytest.approx(cli_run["fast"]["train_psnr"], abs=1e-5)
    assert summary["psnr"] != pytest.approx(cli_run["summary"]["train_psnr"], abs=0.1)  # another model


def test_a_rendered_view_is_the_clis_bit_for_bit(ctx, quarter_test_scene, cli_run):
    view = vknerf.Model.load(cli_run["model"], ctx).render(quarter_test_scene.cameras[0])
    assert view["depth"].tobytes() == cli_run["depth"].tobytes()
    # As the PNG writer rounds: lround(clamp(v, 0, 1) * 255) in float, halves away from zero.
    as_bytes = np.floor((np.clip(view["rgb"], 0, 1) * np.float32(255)).astype(np.float64) + 0.5).astype(np.uint8)
    np.testing.assert_array_equal(as_bytes, cli_run["rgb"][..., :3])
    assert view["opacity"].max() > 0.5  # a scene, not an empty box


def test_a_profiled_render_is_the_same_view_with_its_kernels_timed(ctx, quarter_test_scene, cli_run):
    camera = quarter_test_scene.cameras[0]
    plain = vknerf.Model.load(cli_run["model"], ctx).render(camera)
    profiled = vknerf.Model.load(cli_run["model"], ctx, profile=True).render(camera)
    assert plain["kernel_ms"] == {}
    assert profiled["rgb"].tobytes() == plain["rgb"].tobytes()
    # lavapipe's compute queue has timestamps: every kernel of the render has a row (the model is
    # the vanilla one: its MLP and the composite among them), none negative.
    assert any("composite" in name for name in profiled["kernel_ms"]), profiled["kernel_ms"]
    assert all(ms >= 0 for ms in profiled["kernel_ms"].values())


def test_evaluate_is_the_clis(ctx, quarter_test_scene, cli_run):
    model = vknerf.Model.load(cli_run["model"])
    first = vknerf.Dataset.from_arrays(np.stack([quarter_test_scene.image(i) for i in range(3)]),
                                       quarter_test_scene.poses[:3], quarter_test_scene.cameras[0].intrinsics,
                                       bounds=quarter_test_scene.bounds)
    result = vknerf.evaluate(model, first)
    expected = cli_run["eval"]["images"]
    assert list(result["psnr"]) == [e["psnr"] for e in expected]
    assert list(result["ssim"]) == [e["ssim"] for e in expected]
    assert [v["rgb"].shape for v in model.render_dataset(first)] == [(25, 25, 3)] * 3
