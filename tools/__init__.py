"""Makes tools/ a Python package, so that `python3 -m tools.scenes.<module>` runs from the repository root."""
