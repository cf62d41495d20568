"""Arrays in and out: what goes into Dataset.from_arrays comes back out unchanged, and every bad
array is refused naming the argument, its shape or dtype."""
import numpy as np
import pytest

import vknerf


def test_images_poses_and_box_round_trip(synthetic):
    images, poses, k = synthetic
    box = np.array([[-1, -1, -0.5], [1, 1, 0.5]], np.float32)
    data = vknerf.Dataset.from_arrays(images, poses, k, bounds=box, names=["a", "b", "c", "d"])
    assert len(data) == 4 and data.names == ["a", "b", "c", "d"]
    for i in range(4):
        rgba = data.image(i)
        assert rgba.shape == (12, 16, 4) and rgba.dtype == np.uint8
        np.testing.assert_array_equal(rgba[..., :3], images[i])
        assert (rgba[..., 3] == 255).all()
    np.testing.assert_array_equal(data.poses, poses)
    np.testing.assert_array_equal(data.bounds, box)
    assert data.bounds_source == "given"
    c = data.cameras[1]
    assert (c.width, c.height, c.fx, c.cx) == (16, 12, 20.0, 8.0)
    np.testing.assert_array_equal(c.intrinsics, [[20, 0, 8], [0, 20, 6], [0, 0, 1]])


def test_float_images_rgba_and_per_camera_intrinsics(synthetic):
    images, poses, k = synthetic
    rgba = np.concatenate([images, np.full(images.shape[:3] + (1,), 128, np.uint8)], -1)
    floats = (rgba.astype(np.float32) / 255.0).copy()
    K = np.tile(np.array([[20, 0, 8], [0, 21, 6], [0, 0, 1]], np.float64), (4, 1, 1))
    data = vknerf.Dataset.from_arrays(floats, poses, K)
    np.testing.assert_array_equal(data.image(2), rgba[2])  # 0-1 floats back to the same bytes
    assert data.cameras[3].fy == 21.0
    assert data.bounds_source in ("cameras", "cameras+alpha")


def test_opencv_convention_and_lens(synthetic):
    images, poses, k = synthetic
    cv = poses.copy()
    cv[:, :3, 1:3] *= -1  # OpenCV: +Y down, looking down +Z
    data = vknerf.Dataset.from_arrays(images, cv, k, distortion=[0.01, 0, 0, 0], convention="opencv")
    np.testing.assert_array_equal(data.poses, poses)
    assert data.cameras[0].lens == "opencv"
    np.testing.assert_allclose(data.cameras[0].distortion[:4], [0.01, 0, 0, 0])


def with_nan(images, i):
    floats = images.astype(np.float32) / 255
    floats[i, 3, 4, 1] = np.nan
    return floats


@pytest.mark.parametrize("change, message", [
    (lambda a: a[..., :2], "images must have shape (N, H, W, 3) or (N, H, W, 4) with N >= 1, got (4, 12, 16, 2)"),
    (lambda a: a.astype(np.int16), "images must be uint8 (sRGB values 0-255) or float32 (0-1), got dtype int16"),
    (lambda a: a.astype(np.float64), "got dtype float64"),
    (lambda a: a[:, ::2], "images must be C-contiguous"),
    (lambda a: a[0], "images must have shape"),
    (lambda a: with_nan(a, 2), "images hold a value that is not finite (image 2)"),
])
def test_bad_images(synthetic, change, message):
    images, poses, k = synthetic
    with pytest.raises(vknerf.InvalidArgumentError) as e:
        vknerf.Dataset.from_arrays(change(images), poses, k)
    assert message in str(e.value)
    assert isinstance(e.value, ValueError) and isinstance(e.value, vknerf.Error)


@pytest.mark.parametrize("poses_of, intrinsics, distortion, message", [
    (lambda p: p[:3], None, None, "poses must have shape (N, 4, 4) with N the images' count 4, got (3, 4, 4)"),
    (lambda p: p[:, :3], None, None, "got (4, 3, 4)"),
    (lambda p: p.transpose(0, 2, 1), None, None, "poses must be C-contiguous"),
    (lambda p: p, [20, 20, 8], None, "intrinsics must have shape (4,) fx fy cx cy or (3, 3) K, got (3,)"),
    (lambda p: p, [[20, 1, 8], [0, 20, 6], [0, 0, 1]], None, "no skew"),
    (lambda p: p, [0, 20, 8, 6], None, "focal lengths must be finite and positive"),
    (lambda p: p, None, [0.1, 0.2], "OpenCV distortion is (k1, k2, p1, p2[, k3[, k4, k5, k6]]): 4, 5 or 8 values, got 2"),
    (lambda p: p, None, [-10, 0, 0, 0], "does not invert"),
    (lambda p: p, None, ["a", 0, 0, 0], "distortion must hold numbers"),
])
def test_bad_cameras(synthetic, poses_of, intrinsics, distortion, message):
    images, poses, k = synthetic
    with pytest.raises(ValueError) as e:
        vknerf.Dataset.from_arrays(images, poses_of(poses), k if intrinsics is None else intrinsics, distortion=distortion)
    assert message in str(e.value)


def test_a_synthetic_dataset_trains_and_renders(ctx, synthetic):
    images, poses, k = synthetic
    data = vknerf.Dataset.from_arrays(images, poses, k)
    trainer = vknerf.Trainer(ctx, data, vknerf.TrainConfig.vanilla(ctx, width=32, depth=2, coarse=8, fine=8, rays=256))
    first = trainer.step()
    stats = trainer.step(3)
    assert stats["step"] == 4 and np.isfinite(stats["loss"]) and stats["loss"] > 0 and first["step"] == 1
    view = trainer.model().render(data.cameras[0])
    assert view["rgb"].shape == (12, 16, 3) and view["rgb"].dtype == np.float32
    assert view["depth"].shape == (12, 16) and view["opacity"].shape == (12, 16)
    assert np.isfinite(view["rgb"]).all() and (view["opacity"] >= 0).all() and (view["opacity"] <= 1.0001).all()
    assert view["samples"] == 12 * 16 * (8 + 8 + 8)  # 8 coarse, then 8 + 8 through the fine network, a pixel
