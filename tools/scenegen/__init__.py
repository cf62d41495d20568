"""Parts shared by the scene generators in tools/ (make_scene.py, make_capture.py, make_ffwd_capture.py, and
the python3 steps after them: warp_capture.py, llff_capture.py, check_capture.py)."""
