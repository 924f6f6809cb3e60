"""The coupled loop and what it needs: the build of a scene (build.py), the loop
of every device in Python (run.py) and compiled (engine_kernel.py,
fast_loop.py), where its rows go (recording.py). May import mechanics,
thermal, meshes, schema."""
