# Resampling renders. warp() turns a wide pinhole render into the photo a distorted camera takes from the same
# pose: for each output (sub)pixel, its distorted normalised coordinates are undistorted (lens.py, Newton
# iteration), mapped to the wide render's pixel and sampled bilinearly. The camera model is thus exact, and only
# the render's own resolution limits the detail: render it oversampled (make_capture.py does, 1.5x by default).
# downscale() makes the smaller copies of a photo (LLFF's images_N/).
import numpy as np

from . import lens as lenses


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(c):
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)


def bilinear(img, u, v):
    """img (H x W x C) sampled at pixel coordinates (u, v), centres at +0.5; clamps at the border."""
    h, w = img.shape[:2]
    x = np.clip(u - 0.5, 0.0, w - 1.0)
    y = np.clip(v - 0.5, 0.0, h - 1.0)
    x0 = np.minimum(np.floor(x).astype(np.int64), w - 2)
    y0 = np.minimum(np.floor(y).astype(np.int64), h - 2)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    top = img[y0, x0] * (1 - fx) + img[y0, x0 + 1] * fx
    bottom = img[y0 + 1, x0] * (1 - fx) + img[y0 + 1, x0 + 1] * fx
    return top * (1 - fy) + bottom * fy


def warp(wide, wide_cam, out_cam, lens, supersample=2):
    """wide: H x W x 3 uint8 sRGB pinhole render with intrinsics wide_cam (fl_x fl_y cx cy); returns the
    out_cam["h"] x out_cam["w"] x 3 uint8 image of the camera out_cam with `lens`, each pixel the mean of
    supersample^2 samples over its area, averaged in linear light. Raises if a sample falls outside `wide`."""
    lin = srgb_to_linear(wide.astype(np.float64) / 255.0)
    w, h = int(out_cam["w"]), int(out_cam["h"])
    acc = np.zeros((h, w, 3))
    rows, cols = np.mgrid[0:h, 0:w].astype(np.float64)
    for a in range(supersample):
        for b in range(supersample):
            u = cols + (b + 0.5) / supersample
            v = rows + (a + 0.5) / supersample
            x, y = lenses.undistort(lens, (u - out_cam["cx"]) / out_cam["fl_x"], (v - out_cam["cy"]) / out_cam["fl_y"])
            su = wide_cam["fl_x"] * x + wide_cam["cx"]
            sv = wide_cam["fl_y"] * y + wide_cam["cy"]
            if su.min() < 0 or sv.min() < 0 or su.max() > wide.shape[1] or sv.max() > wide.shape[0]:
                raise ValueError("the wide render does not cover the distorted camera's view")
            acc += bilinear(lin, su, sv)
    out = linear_to_srgb(acc / supersample ** 2)
    return np.round(out * 255.0).astype(np.uint8)


def downscale(img, factor):
    """uint8 H x W x 3 sRGB image -> each factor x factor block's mean in linear light (H and W multiples of
    factor), as if rendered at the lower resolution."""
    h, w = img.shape[0] // factor, img.shape[1] // factor
    if (h * factor, w * factor) != img.shape[:2]:
        raise ValueError(f"{img.shape[1]}x{img.shape[0]} is not a multiple of {factor}")
    lin = srgb_to_linear(img.astype(np.float64) / 255.0).reshape(h, factor, w, factor, -1).mean(axis=(1, 3))
    return np.round(linear_to_srgb(lin) * 255.0).astype(np.uint8)
