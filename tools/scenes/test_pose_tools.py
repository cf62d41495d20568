"""perturb_poses and pose_error on the sample scene (assets/tabletop): every training camera comes out
exactly --degrees and --shift off, true against true scores 0, the same seed writes the same file, and bad
input is refused with one line naming the file and field. Needs numpy, not Blender; about a second.

  python3 -m unittest tools.scenes.test_pose_tools   (from the repository root; ctest runs it as scene_pose_tools)
"""
import filecmp
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "assets", "tabletop")


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


if __name__ == "__main__":
    unittest.main()
