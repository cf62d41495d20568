# Lens distortion models on normalised image coordinates, in numpy, exactly as include/vknerf/camera.h states
# them (OpenCV's conventions: x right, y down, (x, y) = (X/Z, Y/Z); pixel = (fx * x_d + cx, fy * y_d + cy)
# with the image origin at the top-left corner of the top-left pixel, so pixel centres sit at +0.5).
#   pinhole: no distortion.
#   opencv:  r2 = x^2 + y^2, radial = (1 + k1 r2 + k2 r2^2 + k3 r2^3) / (1 + k4 r2 + k5 r2^2 + k6 r2^3),
#            x_d = x radial + 2 p1 x y + p2 (r2 + 2 x^2), y_d = y radial + p1 (r2 + 2 y^2) + 2 p2 x y.
#   fisheye: theta = atan(r), theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
#            (x_d, y_d) = (theta_d / r) (x, y).
# A lens is a dict: {"model": "pinhole" | "opencv" | "fisheye", "k1": .., "k2": .., ...}; missing terms are 0.
# Used inside Blender (to size the wide render) and by python3 (to warp it, and to check the result).
import numpy as np

TERMS = ("k1", "k2", "k3", "k4", "k5", "k6", "p1", "p2")


def term(lens, name):
    return float(lens.get(name, 0.0))


def _opencv_with_jacobian(lens, x, y):
    k1, k2, k3, k4, k5, k6, p1, p2 = (term(lens, n) for n in TERMS)
    r2 = x * x + y * y
    num = 1 + r2 * (k1 + r2 * (k2 + r2 * k3))
    den = 1 + r2 * (k4 + r2 * (k5 + r2 * k6))
    radial = num / den
    dnum = k1 + r2 * (2 * k2 + 3 * k3 * r2)
    dden = k4 + r2 * (2 * k5 + 3 * k6 * r2)
    dradial = (dnum * den - num * dden) / (den * den)  # d radial / d r2
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    jxx = radial + 2 * x * x * dradial + 2 * p1 * y + 6 * p2 * x
    jxy = 2 * x * y * dradial + 2 * p1 * x + 2 * p2 * y
    jyy = radial + 2 * y * y * dradial + 6 * p1 * y + 2 * p2 * x
    return xd, yd, jxx, jxy, jxy, jyy  # the Jacobian is symmetric for this model


def _fisheye_theta_d(lens, theta):
    t2 = theta * theta
    k1, k2, k3, k4 = (term(lens, n) for n in ("k1", "k2", "k3", "k4"))
    return theta * (1 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))))


def distort(lens, x, y):
    """Undistorted normalised coordinates -> distorted ones."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    model = lens.get("model", "pinhole")
    if model == "pinhole":
        return x.copy(), y.copy()
    if model == "opencv":
        return _opencv_with_jacobian(lens, x, y)[:2]
    if model == "fisheye":
        r = np.hypot(x, y)
        theta = np.arctan(r)
        # theta_d / r -> 1 as r -> 0.
        scale = np.where(r > 1e-12, _fisheye_theta_d(lens, theta) / np.maximum(r, 1e-12), 1.0)
        return x * scale, y * scale
    raise ValueError(f"unknown lens model {model!r}")


def undistort(lens, xd, yd, iterations=30, tol=1e-12):
    """Distorted normalised coordinates -> undistorted ones, by Newton iteration; raises if it does not converge."""
    xd, yd = np.asarray(xd, float), np.asarray(yd, float)
    model = lens.get("model", "pinhole")
    if model == "pinhole":
        return xd.copy(), yd.copy()
    if model == "opencv":
        x, y = xd.copy(), yd.copy()
        for _ in range(iterations):
            fx, fy, jxx, jxy, jyx, jyy = _opencv_with_jacobian(lens, x, y)
            ex, ey = fx - xd, fy - yd
            det = jxx * jyy - jxy * jyx
            x = x - (jyy * ex - jxy * ey) / det
            y = y - (jxx * ey - jyx * ex) / det
        residual = np.hypot(*(np.stack(distort(lens, x, y)) - np.stack([xd, yd])))
    elif model == "fisheye":
        rd = np.hypot(xd, yd)
        theta = np.minimum(rd, 1.5)
        k1, k2, k3, k4 = (term(lens, n) for n in ("k1", "k2", "k3", "k4"))
        for _ in range(iterations):
            t2 = theta * theta
            deriv = 1 + t2 * (3 * k1 + t2 * (5 * k2 + t2 * (7 * k3 + t2 * 9 * k4)))
            theta = theta - (_fisheye_theta_d(lens, theta) - rd) / deriv
        if np.any(theta >= np.pi / 2) or np.any(theta < 0):
            raise ValueError("fisheye undistortion left the forward hemisphere")
        residual = np.abs(_fisheye_theta_d(lens, theta) - rd)
        scale = np.where(rd > 1e-12, np.tan(theta) / np.maximum(rd, 1e-12), 1.0)
        x, y = xd * scale, yd * scale
    else:
        raise ValueError(f"unknown lens model {model!r}")
    if not np.all(np.isfinite(residual)) or residual.max(initial=0.0) > tol:
        raise ValueError(f"undistortion did not converge (residual {residual.max():.3g}): lens {lens}")
    return x, y


def border_extent(lens, fx, fy, cx, cy, width, height, steps=64):
    """Largest |x| and |y| (undistorted, normalised) over the image border, pixel corners included."""
    u = np.linspace(0, width, steps)
    v = np.linspace(0, height, steps)
    bu = np.concatenate([u, u, np.zeros(steps), np.full(steps, float(width))])
    bv = np.concatenate([np.zeros(steps), np.full(steps, float(height)), v, v])
    x, y = undistort(lens, (bu - cx) / fx, (bv - cy) / fy)
    return float(np.abs(x).max()), float(np.abs(y).max())


def project(lens, cam, points_cam):
    """OpenCV-frame camera points (N x 3, z forward) -> distorted pixel coordinates (N x 2) and a z > 0 mask."""
    z = points_cam[:, 2]
    safe = np.where(z > 1e-9, z, 1.0)
    xd, yd = distort(lens, points_cam[:, 0] / safe, points_cam[:, 1] / safe)
    return np.stack([cam["fl_x"] * xd + cam["cx"], cam["fl_y"] * yd + cam["cy"]], axis=1), z > 1e-9
