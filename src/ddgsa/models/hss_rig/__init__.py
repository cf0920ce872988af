"""High-speed-shaft drive-train test rig (thesis paper A, seed 001)."""
