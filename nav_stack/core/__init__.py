"""Pure algorithms of nav_stack: numpy only, no ROS (checked by import-linter)."""
