"""Scene generation for vknerf's tests and measurements, one package run from the repository root.

Blender scenes (run inside Blender by the shell scripts here, through need_blender.sh's blender_module):
make_scene (the sample scene assets/tabletop, and the 800x800 large dataset), make_capture (a hand-held,
lens-distorted capture; wall_scene is its --scene wall), make_ffwd_capture (a forward-facing capture),
make_detail_object (a detailed nerf_synthetic-style object for full-resolution detail).
python3 steps after them and standalone scenes, each `python3 -m tools.scenes.<name> --help`:
warp_capture, llff_capture, check_capture, check_scene, make_unbounded_scene, upscale_scene; for camera
refinement, perturb_poses (training poses off by known amounts) and pose_error (scores poses against the
true ones), tested by test_pose_tools (ctest scene_pose_tools).
Shared parts: blender_parts (Blender only), lens, warp, colmap_model, transforms_json, poses, png_file.
"""
