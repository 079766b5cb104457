# Included by every interface package right before rosidl_generate_interfaces(): generate, and
# compile quickly, only the code rclpy loads.
#
# This project uses its interfaces from Python only. rclpy loads the Python extension
# (rosidl_generator_py), which hands rcl the C type support (rosidl_typesupport_c); that one
# dispatches at run time to the Fast DDS C type support (rosidl_typesupport_fastrtps_c, what
# rmw_fastrtps_cpp serializes C messages with) or to the C introspection type support
# (rosidl_typesupport_introspection_c). rosidl_generator_c writes the structs they all use, with the
# RIHS01 type hashes rosidl_generator_type_description computes (interfaces/type_hashes.json). The
# C++ generator and the three C++ type supports are loaded by nothing here, yet they were more than
# half of the build (rosidl_typesupport_fastrtps_cpp most of all).
#
# 1. Which generators run. rosidl_generate_interfaces() runs every generator that registered itself
#    on the extension point "rosidl_generate_idl_interfaces" when its CMake package was found, and
#    finding the message packages from pip (std_msgs, geometry_msgs, ...) finds the C++ type supports
#    as their exported dependencies: choosing what to find_package() is not enough. So we keep, in
#    registration order (a generator registers after the ones it needs), only the list below.
set(_navsuite_rclpy_generators
  rosidl_generator_type_description
  rosidl_generator_c
  rosidl_typesupport_fastrtps_c
  rosidl_typesupport_introspection_c
  rosidl_typesupport_c
  rosidl_generator_py
)
set(_navsuite_kept_extensions "")
set(_navsuite_kept_generators "")
foreach(_navsuite_extension IN LISTS AMENT_EXTENSIONS_rosidl_generate_idl_interfaces)
  string(REGEX REPLACE ":.*$" "" _navsuite_generator "${_navsuite_extension}")
  if(_navsuite_generator IN_LIST _navsuite_rclpy_generators)
    list(APPEND _navsuite_kept_extensions "${_navsuite_extension}")
    list(APPEND _navsuite_kept_generators "${_navsuite_generator}")
  endif()
endforeach()
foreach(_navsuite_generator IN LISTS _navsuite_rclpy_generators)
  if(NOT _navsuite_generator IN_LIST _navsuite_kept_generators)
    message(FATAL_ERROR "rclpy_typesupports: the generator '${_navsuite_generator}' was not found "
      "(find_package(rosidl_default_generators) before including this file)")
  endif()
endforeach()
set(AMENT_EXTENSIONS_rosidl_generate_idl_interfaces ${_navsuite_kept_extensions})
message(STATUS "Generating for rclpy only: ${_navsuite_kept_generators}")

# 2. How they compile. Each generated C++ file of the Fast DDS type support spends most of its
#    compile time parsing the same Fast CDR headers, so the generated libraries are unity builds:
#    CMake concatenates up to 8 sources per translation unit (UNITY_BUILD_BATCH_SIZE's default),
#    which for nav2_msgs' 51 interfaces means 7 compiler runs instead of 51 per library.
#    rosidl_generator_c's *__description.c files stay out: each defines the same static names.
#    The targets exist only after rosidl_generate_interfaces(), hence the deferred call.
function(_navsuite_unity_build_generated_libraries)
  foreach(_generator IN ITEMS rosidl_generator_c rosidl_typesupport_fastrtps_c
      rosidl_typesupport_introspection_c rosidl_typesupport_c rosidl_generator_py)
    set(_target ${PROJECT_NAME}__${_generator})
    if(TARGET ${_target})
      set_target_properties(${_target} PROPERTIES UNITY_BUILD ON)
      get_target_property(_sources ${_target} SOURCES)
      list(FILTER _sources INCLUDE REGEX "__description\\.c$")
      if(_sources)
        set_source_files_properties(${_sources} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
      endif()
    endif()
  endforeach()
endfunction()
cmake_language(DEFER CALL _navsuite_unity_build_generated_libraries)
