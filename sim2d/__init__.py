"""sim2d: a pymunk 2D differential-drive TurtleBot3 simulator on the ROS 2 graph.

``sim2d.core`` holds the world, robot, lidar, odometry and battery models (pymunk + numpy, no ROS);
``sim2d.ros`` publishes them as a Gazebo-like ROS surface (/scan, /odom, /tf, /clock, /battery_state).
"""
