"""The training cameras as arrays: a trainer's are the dataset's until it refines them, then move
a little; a checkpoint records them as the trainer had them."""
import numpy as np

import vknerf
from helpers import FAST_FIELDS


def test_refined_poses_move_and_are_recorded(ctx, quarter_scene, tmp_path):
    still = vknerf.Trainer(ctx, quarter_scene, vknerf.TrainConfig.fast(ctx, **FAST_FIELDS))
    np.testing.assert_array_equal(still.poses(), quarter_scene.poses)
    refining = vknerf.Trainer(ctx, quarter_scene, vknerf.TrainConfig.fast(ctx, refine_cameras=True, camera_lr=1e-3,
                                                                          **FAST_FIELDS))
    refining.step(5)
    poses = refining.poses()
    assert poses.shape == (len(quarter_scene), 4, 4) and poses.dtype == np.float32
    moved = np.abs(poses - quarter_scene.poses).max()
    assert 0 < moved < 0.05, moved
    np.testing.assert_array_equal(np.stack([c.pose for c in refining.cameras()]), poses)
    path = str(tmp_path / "refined.vknerf")
    refining.save(path)
    recorded = vknerf.Model.load(path, ctx).training_cameras()
    np.testing.assert_array_equal(np.stack([c.pose for c in recorded]), poses)
