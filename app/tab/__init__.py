"""One browser tab at run time: its session (the loop) and the per-tab helpers."""
