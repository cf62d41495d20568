# What the tools that write a changed copy of a nerf_synthetic-style scene share (perturb_poses,
# change_exposure): reading the split jsons, finding each frame's image the way the loader does, linking the
# image folders instead of copying them, and a marker file so that a tool only ever rewrites a folder it made.
import json
import os

from .poses import IMAGE_EXTENSIONS, fail, frame_poses, read_json

SPLITS = ("train", "val", "test")


def read_splits(scene, chosen):
    """{split: meta} of every transforms_<split>.json in the scene (the chosen one must be there), each frame
    checked before anything is written, so bad input never leaves a half-written OUT."""
    metas = {}
    for split in SPLITS:
        p = os.path.join(scene, f"transforms_{split}.json")
        if os.path.exists(p) or split == chosen:
            metas[split] = read_json(p)
            frame_poses(p, metas[split])
    return metas


def refuse_scene_folder(scene, out):
    # Writing into the scene itself would replace the jsons the copy is made from.
    if os.path.exists(out) and os.path.realpath(out) == os.path.realpath(scene):
        raise SystemExit(f"{out}: is the scene folder itself; name a new folder")


def find_image(scene, path, i, name):
    """The file the loader opens for frames[i].file_path `name` of the json `path`: resolved against the
    scene folder, as written or with .png, .jpg, .jpeg appended (any case); exits naming the field if none."""
    base = os.path.join(scene, name)
    found = next((p for p in [base] + [base + e for x in IMAGE_EXTENSIONS for e in (x, x.upper())]
                  if os.path.isfile(p)), None)
    if found is None:
        fail(path, f"frames[{i}].file_path", f"names no image: {base} (also with .png, .jpg, .jpeg)")
    return found


def image_links(scene, path, meta):
    """{name in OUT: absolute path in the scene}: what makes every frame's image reachable from OUT. The
    loader resolves file_path against the json's folder, as it is or with .png, .jpg, .jpeg."""
    links = {}
    for i, fr in enumerate(meta["frames"]):
        name = fr["file_path"]
        found = find_image(scene, path, i, name)
        if os.path.isabs(name):
            continue  # reachable from anywhere
        rel, parts = os.path.normpath(name), [p for p in name.split("/") if p not in ("", ".")]
        if rel == ".." or rel.startswith("../") or parts[0] == "..":
            fail(path, f"frames[{i}].file_path", f"{name} leaves the scene folder: a link in OUT cannot reach it")
        # A folder of images is linked whole (the path's first folder as written: the loader does not
        # normalise "sub/../x"); an image beside the json is linked as the file found.
        top = parts[0] if len(parts) > 1 else os.path.relpath(found, scene)
        links[top] = os.path.abspath(os.path.join(scene, top))
    return links


def check_link_names(scene, links, outputs, marker, tool):
    # A link named like a file the tool writes would be overwritten by it (or stop it writing).
    for name in links:
        if name in outputs or name == marker:
            raise SystemExit(f"{scene}: the image path {name} has the name of a file {tool} writes")


def marked_entries(out, marker, tool):
    """The entries OUT's marker lists; exits if OUT has no marker (someone else's folder) or a bad one."""
    path = os.path.join(out, marker)
    if not os.path.isfile(path):
        raise SystemExit(f"{out}: not empty and not written by {tool} (no {marker}); "
                         "name a new folder or empty this one")
    try:
        with open(path) as f:
            made = json.load(f).get("entries", [])
    except (ValueError, AttributeError, UnicodeDecodeError):
        raise SystemExit(f"{path}: is not the JSON object {tool} writes; empty {out} by hand") from None
    for name in made if isinstance(made, list) else [made]:
        # A marker edited by hand must not reach outside OUT.
        if not isinstance(name, str) or not name or os.path.isabs(name) or ".." in name.split("/"):
            raise SystemExit(f"{path}: field 'entries' lists {name!r}, which is not a name inside {out}")
    return made


def prepare_out(out, marker, tool):
    """Empties the entries an earlier run listed in OUT's marker; refuses any other non-empty OUT.

    Entries are links and files, removed; an entry ending in "/" is a folder the tool made, removed once the
    files listed in it are gone, and refused if it still holds anything else. Nothing unlisted is deleted."""
    if os.path.exists(out) and not os.path.isdir(out):
        raise SystemExit(f"{out}: exists and is not a folder")
    os.makedirs(out, exist_ok=True)
    if not os.listdir(out):
        return
    made = marked_entries(out, marker, tool)
    for name in [n for n in made if not n.endswith("/")]:
        p = os.path.join(out, name)
        if os.path.islink(p) or os.path.isfile(p):
            os.unlink(p)
        elif os.path.exists(p):
            raise SystemExit(f"{p}: listed in {marker} but is a folder, not a link or file: remove it by hand")
    for name in sorted((n for n in made if n.endswith("/")), key=len, reverse=True):  # inner folders first
        p = os.path.join(out, name.rstrip("/"))
        if os.path.islink(p) or (os.path.exists(p) and not os.path.isdir(p)):
            raise SystemExit(f"{p}: listed in {marker} as a folder it made, but is not one: remove it by hand")
        if os.path.isdir(p):
            if os.listdir(p):
                raise SystemExit(f"{p}: a folder {tool} made, but it holds files it did not write: "
                                 "remove them by hand")
            os.rmdir(p)
    os.unlink(os.path.join(out, marker))  # last: a run stopped above still finds OUT marked as this tool's


def write_marker(out, marker, tool, scene, settings, entries):
    # Written in OUT so that the next run may empty what this one made, and nothing else.
    with open(os.path.join(out, marker), "w") as f:
        json.dump({"made_by": f"python3 -m tools.scenes.{tool}", "scene": os.path.abspath(scene), **settings,
                   "entries": entries}, f, indent=2)
        f.write("\n")
