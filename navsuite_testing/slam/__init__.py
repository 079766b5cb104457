"""SLAM rigs: analytic worlds and lidar (world), the fake robot (fakes), the slam node's probe and
drive (node_probe), the exploration stack (stack) and its ground-truth probe (system_probe)."""
