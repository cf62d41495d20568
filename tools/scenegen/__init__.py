"""Parts shared by the scene generators in tools/ (make_scene.py, make_capture.py, check_capture.py)."""
