"""Client libraries (SMACC2's smacc2_client_library): cl_nav2z, cl_ros2_timer, cl_keyboard."""
