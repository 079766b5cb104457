"""Pure simulation models of sim2d: pymunk and numpy only, no ROS (checked by import-linter)."""
