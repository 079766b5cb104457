# Included by fix_wheel_include_dirs.cmake, the CMAKE_PROJECT_INCLUDE of every interface package.
#
# ament's resource index, which tells rosidl which typesupports exist (rosidl_typesupport_c/_cpp,
# fastrtps, introspection), is searched only along the AMENT_PREFIX_PATH environment variable that
# sourcing a ROS installation sets. Our ROS 2 comes from pip and nothing is sourced, so without this
# rosidl_generate_interfaces stops with "No 'rosidl_typesupport_c' found". We put the prefixes of
# CMAKE_PREFIX_PATH (the staging prefix, then the venv) in front of whatever AMENT_PREFIX_PATH
# holds, so the venv's typesupports win over a sourced ROS. This changes the environment of this
# configure run only.
set(_navsuite_ament_prefix_path "${CMAKE_PREFIX_PATH}")
if(NOT "$ENV{AMENT_PREFIX_PATH}" STREQUAL "")
  string(REPLACE ":" ";" _navsuite_sourced "$ENV{AMENT_PREFIX_PATH}")
  list(APPEND _navsuite_ament_prefix_path ${_navsuite_sourced})
endif()
list(REMOVE_DUPLICATES _navsuite_ament_prefix_path)
string(REPLACE ";" ":" _navsuite_ament_prefix_path "${_navsuite_ament_prefix_path}")
set(ENV{AMENT_PREFIX_PATH} "${_navsuite_ament_prefix_path}")
