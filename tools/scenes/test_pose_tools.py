"""perturb_poses and pose_error on the sample scene (assets/tabletop): every training camera comes out
exactly --degrees and --shift off, true against true scores 0, the same seed writes the same file, and bad
input is refused with one line naming the file and field. change_exposure likewise: every training photo is
the original times its recorded factors, the test split untouched, the same seed the same files; and png_file,
the PNG reader it shares with upscale_scene, against PNGs filtered here. Needs numpy, not Blender; a few seconds.

  python3 -m unittest tools.scenes.test_pose_tools   (from the repository root; ctest runs it as scene_pose_tools)
"""
import filecmp
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest
import zlib

import numpy as np

from tools.scenes import png_file, upscale_scene
from tools.scenes.change_exposure import read_png

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "assets", "tabletop")


def write_filtered_png(path, pixels, colour=None):
    """pixels (height, width, 1 to 4) as a PNG whose rows take the five filters in turn. png_file writes no
    filter, so its reader is checked against this forward filter (the PNG spec's, in numpy) instead."""
    height, width, bpp = pixels.shape
    p = np.zeros((height + 1, width + 1, bpp), np.int32)  # zeros above and to the left, as PNG defines
    p[1:, 1:] = pixels
    raw = b""
    for y in range(height):
        x, a, b, c = p[y + 1, 1:], p[y + 1, :-1], p[y, 1:], p[y, :-1]
        pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
        paeth = np.where((pa <= pb) & (pa <= pc), a, np.where(pb <= pc, b, c))
        kind = y % 5
        raw += bytes([kind]) + ((x - [0, a, b, (a + b) // 2, paeth][kind]) & 255).astype(np.uint8).tobytes()

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, {1: 0, 2: 4, 3: 2, 4: 6}[bpp] if colour is None else colour,
                       0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) +
                chunk(b"IEND", b""))


def run(module, *args):
    return subprocess.run([sys.executable, "-m", f"tools.scenes.{module}", *args], cwd=ROOT,
                          capture_output=True, text=True)


class PoseToolsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="pose_tools_")
        cls.out = os.path.join(cls.tmp, "perturbed")
        cls.first = run("perturb_poses", SCENE, cls.out, "--degrees", "1.0", "--shift", "0.015")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def errors(self, true, estimate):
        report = os.path.join(self.tmp, "error.json")
        r = run("pose_error", true, estimate, "--json", report)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(report) as f:
            return json.load(f)

    def test_every_camera_is_off_by_exactly_the_amounts_asked(self):
        self.assertEqual(self.first.returncode, 0, self.first.stderr)
        self.assertIn("scene centre (0, 0, 0.1): the aabb centre", self.first.stdout)
        e = self.errors(os.path.join(self.out, "transforms_train_true.json"),
                        os.path.join(self.out, "transforms_train.json"))
        self.assertEqual(e["frames_matched"], 100)
        for fr in e["per_frame"]:
            self.assertAlmostEqual(fr["rotation_deg"], 1.0, delta=1e-4, msg=fr["file_path"])
            self.assertAlmostEqual(fr["translation_pct"], 1.5, delta=1e-4, msg=fr["file_path"])
        same = self.errors(os.path.join(self.out, "transforms_train_true.json"),
                           os.path.join(self.out, "transforms_train_true.json"))
        self.assertLess(same["rotation_deg"]["max"], 1e-6)
        self.assertEqual(same["translation_pct"]["max"], 0)

    def test_frames_match_by_the_photo_they_name_from_each_files_folder(self):
        # `vknerf export cameras` writes elsewhere, naming photos by absolute path or from its folder.
        with open(os.path.join(self.out, "transforms_train.json")) as f:
            meta = json.load(f)
        elsewhere = os.path.join(self.tmp, "exported")
        os.makedirs(elsewhere, exist_ok=True)
        for i, fr in enumerate(meta["frames"]):
            photo = os.path.join(self.out, fr["file_path"]) + ".png"
            fr["file_path"] = photo if i % 2 else os.path.relpath(photo, elsewhere)
        estimate = os.path.join(elsewhere, "transforms.json")
        with open(estimate, "w") as f:
            json.dump(meta, f)
        e = self.errors(os.path.join(self.out, "transforms_train_true.json"), estimate)
        self.assertEqual(e["frames_matched"], 100)
        self.assertAlmostEqual(e["rotation_deg"]["max"], 1.0, delta=1e-4)

    def test_the_rest_of_the_scene_is_unchanged_and_reachable(self):
        self.assertTrue(filecmp.cmp(os.path.join(SCENE, "transforms_test.json"),
                                    os.path.join(self.out, "transforms_test.json"), shallow=False))
        self.assertTrue(filecmp.cmp(os.path.join(SCENE, "transforms_train.json"),
                                    os.path.join(self.out, "transforms_train_true.json"), shallow=False))
        with open(os.path.join(self.out, "transforms_train.json")) as f:
            meta = json.load(f)
        with open(os.path.join(SCENE, "transforms_train.json")) as f:
            orig = json.load(f)
        self.assertEqual({k: v for k, v in meta.items() if k != "frames"}, {k: v for k, v in orig.items() if k != "frames"})
        self.assertEqual([fr["file_path"] for fr in meta["frames"]], [fr["file_path"] for fr in orig["frames"]])
        for split in ("train", "test"):
            self.assertTrue(os.path.islink(os.path.join(self.out, split)))
            self.assertTrue(os.path.isfile(os.path.join(self.out, split, "r_0.png")))

    def test_the_same_seed_writes_the_same_file_and_a_foreign_folder_is_refused(self):
        again = os.path.join(self.tmp, "again")
        shutil.copytree(self.out, again, symlinks=True)  # a folder perturb_poses made: rewritten in place
        r = run("perturb_poses", SCENE, again, "--degrees", "1.0", "--shift", "0.015", "--seed", "0")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(filecmp.cmp(os.path.join(self.out, "transforms_train.json"),
                                    os.path.join(again, "transforms_train.json"), shallow=False))
        foreign = os.path.join(self.tmp, "foreign")
        os.makedirs(foreign)
        open(os.path.join(foreign, "notes.txt"), "w").close()
        r = run("perturb_poses", SCENE, foreign, "--degrees", "1.0", "--shift", "0.015")
        self.assertEqual(r.returncode, 1)
        self.assertIn("not written by perturb_poses", r.stderr)
        self.assertEqual(os.listdir(foreign), ["notes.txt"])

    def test_bad_input_names_the_file_and_field(self):
        with open(os.path.join(SCENE, "transforms_train.json")) as f:
            meta = json.load(f)
        meta["frames"][3]["transform_matrix"][1][2] = float("nan")
        bad = os.path.join(self.tmp, "nan.json")
        with open(bad, "w") as f:
            json.dump(meta, f)
        r = run("pose_error", os.path.join(SCENE, "transforms_train.json"), bad)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr.strip(), f"{bad}: field 'frames[3].transform_matrix' holds a value that is not "
                                           "finite (NaN or infinity)")
        r = run("pose_error", os.path.join(SCENE, "transforms_train.json"), os.path.join(self.tmp, "missing.json"))
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr.strip(), f"{os.path.join(self.tmp, 'missing.json')}: no such file")


class ChangeExposureTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="change_exposure_")
        cls.out = os.path.join(cls.tmp, "exposed")
        cls.first = run("change_exposure", SCENE, cls.out, "--low", "0.7", "--high", "1.3", "--white-balance", "0.1")
        if cls.first.returncode:  # every test reads its output: say why once, not with a missing file each
            shutil.rmtree(cls.tmp)
            raise AssertionError(f"change_exposure exited {cls.first.returncode}: {cls.first.stderr}")
        with open(os.path.join(cls.out, "exposures_train.json")) as f:
            cls.table = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_every_photo_is_the_original_times_its_factors(self):
        with open(os.path.join(SCENE, "transforms_train.json")) as f:
            orig = json.load(f)
        rows = self.table["frames"]
        self.assertEqual([r["original"] for r in rows], [fr["file_path"] for fr in orig["frames"]])
        factors = np.array([r["factors"] for r in rows])
        self.assertTrue(np.all((factors[:, 0] >= 0.7) & (factors[:, 0] <= 1.3)))
        self.assertTrue(np.all((factors[:, 1:] >= 0.9) & (factors[:, 1:] <= 1.1)))
        self.assertGreater(factors[:, 0].std(), 0.1)  # drawn per photo, not one for all
        clipped = 0
        for r, f in zip(rows, factors):
            before = read_png(os.path.join(SCENE, r["original"] + ".png")).astype(float)
            after = read_png(os.path.join(self.out, r["file_path"] + ".png")).astype(float)
            want = before[..., :3] * (f[0] * f[1:])
            room = want <= 255
            # Rounded to 8 bits where it fits, 255 where it does not; alpha as it was.
            self.assertLessEqual(np.abs(after[..., :3] - want)[room].max(), 0.5 + 1e-9, r["file_path"])
            self.assertTrue(np.all(after[..., :3][~room] == 255), r["file_path"])
            self.assertTrue(np.array_equal(after[..., 3], before[..., 3]), r["file_path"])
            clipped += (~room).sum()
        self.assertGreater(clipped, 0)  # the sample scene's whites do clip at 1.3: that branch is tested too

    def test_the_shared_reader_undoes_every_filter_for_both_tools(self):
        # change_exposure and upscale_scene read through png_file: every filter, grey made RGB, RGB made RGBA
        # by upscale_scene, and what is not read refused in one line naming the file.
        rng = np.random.default_rng(1)
        for channels in (1, 2, 3, 4):
            pixels = rng.integers(0, 256, (11, 7, channels), np.uint8)
            pixels[:6] //= 64  # small values in the first Paeth row and the one above it, so that ties are taken
            png = os.path.join(self.tmp, f"filtered_{channels}.png")
            write_filtered_png(png, pixels)
            colour = pixels if channels >= 3 else np.concatenate([pixels[..., :1]] * 3 + [pixels[..., 1:]], axis=2)
            self.assertTrue(np.array_equal(read_png(png), colour), channels)
            big = os.path.join(self.tmp, f"big_{channels}.png")
            upscale_scene.enlarge(png, big, 2)
            opaque = np.full(colour.shape[:2] + (1,), 255, np.uint8)
            rgba = colour if colour.shape[2] == 4 else np.concatenate([colour, opaque], axis=2)
            self.assertTrue(np.array_equal(read_png(big), rgba.repeat(2, axis=0).repeat(2, axis=1)), channels)
        palette = os.path.join(self.tmp, "palette.png")
        write_filtered_png(palette, pixels[..., :1], colour=3)
        with self.assertRaises(png_file.PngError) as e:
            read_png(palette)
        self.assertEqual(str(e.exception), f"{palette}: is not an 8-bit grey or RGB(A) PNG without interlacing "
                                           "(palette, 16-bit and interlaced PNGs are not read)")

    def test_the_json_points_at_the_new_photos_and_the_test_split_is_unchanged(self):
        with open(os.path.join(self.out, "transforms_train.json")) as f:
            meta = json.load(f)
        with open(os.path.join(SCENE, "transforms_train.json")) as f:
            orig = json.load(f)
        self.assertEqual({k: v for k, v in meta.items() if k != "frames"},
                         {k: v for k, v in orig.items() if k != "frames"})
        self.assertEqual([{k: v for k, v in fr.items() if k != "file_path"} for fr in meta["frames"]],
                         [{k: v for k, v in fr.items() if k != "file_path"} for fr in orig["frames"]])
        self.assertEqual([fr["file_path"] for fr in meta["frames"]], [r["file_path"] for r in self.table["frames"]])
        self.assertEqual(meta["frames"][7]["file_path"], "./train_exposure/07_r_7")
        self.assertEqual(len(os.listdir(os.path.join(self.out, "train_exposure"))), 100)
        self.assertTrue(filecmp.cmp(os.path.join(SCENE, "transforms_test.json"),
                                    os.path.join(self.out, "transforms_test.json"), shallow=False))
        self.assertTrue(os.path.islink(os.path.join(self.out, "test")))
        self.assertTrue(filecmp.cmp(os.path.join(SCENE, "test", "r_0.png"),
                                    os.path.join(self.out, "test", "r_0.png"), shallow=False))
        self.assertFalse(os.path.exists(os.path.join(self.out, "train")))  # the changed split is not linked

    def test_the_same_seed_writes_the_same_files(self):
        again = os.path.join(self.tmp, "again")
        shutil.copytree(self.out, again, symlinks=True)  # a folder change_exposure made: rewritten in place
        with open(os.path.join(again, "train_exposure", "05_r_5.png"), "wb") as f:
            f.write(b"spoiled")  # so that a run leaving the old files would not pass
        r = run("change_exposure", SCENE, again, "--seed", "0")
        self.assertEqual(r.returncode, 0, r.stderr)
        names = sorted(os.listdir(os.path.join(self.out, "train_exposure")))
        self.assertEqual(sorted(os.listdir(os.path.join(again, "train_exposure"))), names)
        files = ["transforms_train.json", "exposures_train.json", ".change_exposure.json"]
        _, mismatch, errors = filecmp.cmpfiles(self.out, again, files + [f"train_exposure/{n}" for n in names],
                                               shallow=False)
        self.assertEqual((mismatch, errors), ([], []))

    def test_bad_input_is_one_line_and_writes_nothing(self):
        bad = os.path.join(self.tmp, "bad")
        for args, line in (
                (["--low", "1.4", "--high", "1.2"], "--low 1.4 is above --high 1.2: the range [low, high] is empty"),
                (["--white-balance", "nan"], "--white-balance: must be a finite number, not nan"),
                (["--low", "0"], "--low: must be positive (a factor of exposure), not 0")):
            r = run("change_exposure", SCENE, bad, *args)
            self.assertEqual((r.returncode, r.stderr.strip()), (1, line))
        scene = os.path.join(self.tmp, "scene")
        os.makedirs(scene)
        os.symlink(os.path.join(SCENE, "train"), os.path.join(scene, "train"))
        with open(os.path.join(SCENE, "transforms_train.json")) as f:
            meta = json.load(f)
        meta["frames"][2]["file_path"] = "./train/missing"
        with open(os.path.join(scene, "transforms_train.json"), "w") as f:
            json.dump(meta, f)
        r = run("change_exposure", scene, bad)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr.strip(), f"{scene}/transforms_train.json: field 'frames[2].file_path' names no "
                                           f"image: {scene}/./train/missing (also with .png, .jpg, .jpeg)")
        self.assertFalse(os.path.exists(bad))
        r = run("change_exposure", SCENE, SCENE)
        self.assertEqual((r.returncode, r.stderr.strip()),
                         (1, f"{SCENE}: is the scene folder itself; name a new folder"))


if __name__ == "__main__":
    unittest.main()
