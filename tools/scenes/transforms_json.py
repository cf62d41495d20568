# Writes a transforms*.json (nerf_synthetic / instant-ngp keys) by hand, so that each matrix row stays on one
# line and the files read well in a diff. Plain python: used inside Blender and by python3.
import json


def write_transforms(path, header, frames):
    # header: top-level keys in order (e.g. camera_angle_x, aabb); frames: dicts with "file_path" and
    # "transform_matrix" (4 rows of 4 numbers), written in that order.
    lines = ["{"] + [f"  {json.dumps(k)}: {json.dumps(v)}," for k, v in header.items()] + ['  "frames": [']
    for i, fr in enumerate(frames):
        rows = ",\n        ".join(json.dumps(r) for r in fr["transform_matrix"])
        comma = "," if i + 1 < len(frames) else ""
        lines += ["    {", f'      "file_path": {json.dumps(fr["file_path"])},',
                  f'      "transform_matrix": [\n        {rows}\n      ]', "    }" + comma]
    lines += ["  ]", "}", ""]
    text = "\n".join(lines)
    json.loads(text)  # fail here, not in a loader, if the hand-written JSON were malformed
    with open(path, "w") as f:
        f.write(text)
