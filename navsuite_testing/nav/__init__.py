"""Navigation rigs: in-process nodes on the real map (world) and a vectorised fake lidar (fake_lidar)."""
