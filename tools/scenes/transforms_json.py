# Writes a transforms*.json (nerf_synthetic / instant-ngp keys) by hand, so that each matrix row stays on one
# line and the files read well in a diff. Plain python: used inside Blender and by python3.
import json


def write_transforms(path, header, frames):
    # header: top-level keys in order (e.g. camera_angle_x, aabb); frames: dicts with "file_path" and
    # "transform_matrix" (4 rows of 4 numbers) and any other keys of a frame (per-frame intrinsics), each
    # written in the dict's order.
    lines = ["{"] + [f"  {json.dumps(k)}: {json.dumps(v)}," for k, v in header.items()] + ['  "frames": [']
    for i, fr in enumerate(frames):
        keys = []
        for k, v in fr.items():
            if k == "transform_matrix":
                rows = ",\n        ".join(json.dumps(r) for r in v)
                keys.append(f'      "transform_matrix": [\n        {rows}\n      ]')
            else:
                keys.append(f"      {json.dumps(k)}: {json.dumps(v)}")
        comma = "," if i + 1 < len(frames) else ""
        lines += ["    {", ",\n".join(keys), "    }" + comma]
    lines += ["  ]", "}", ""]
    text = "\n".join(lines)
    json.loads(text)  # fail here, not in a loader, if the hand-written JSON were malformed
    with open(path, "w") as f:
        f.write(text)
