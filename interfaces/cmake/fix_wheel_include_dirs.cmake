# Injected into every interface package with -DCMAKE_PROJECT_INCLUDE (see scripts/build_interfaces.py).
#
# The ROS 2 Jazzy message wheels were built in a manylinux container, and their exported CMake
# targets (e.g. builtin_interfaces::builtin_interfaces__rosidl_generator_py) list that container's
# include folders, /opt/python/cp3XX-cp3XX/include/python3.X and its numpy include, which do not
# exist here. CMake's generate step rejects imported targets with missing include folders.
# At the end of configuration we rewrite every such path to this interpreter's headers
# (NAVSUITE_PYTHON_INCLUDE_DIR) or numpy's (NAVSUITE_NUMPY_INCLUDE_DIR), and drop any other
# missing /opt/python path. Nothing on disk is edited and no root is needed.

function(_navsuite_fix_wheel_include_dirs)
  get_property(targets DIRECTORY "${CMAKE_SOURCE_DIR}" PROPERTY IMPORTED_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
    if(NOT dirs)
      continue()
    endif()
    set(fixed "")
    set(changed FALSE)
    foreach(dir IN LISTS dirs)
      if(dir MATCHES "^/opt/python/" AND NOT EXISTS "${dir}")
        set(changed TRUE)
        if(dir MATCHES "numpy")
          list(APPEND fixed "${NAVSUITE_NUMPY_INCLUDE_DIR}")
        elseif(dir MATCHES "include/python")
          list(APPEND fixed "${NAVSUITE_PYTHON_INCLUDE_DIR}")
        endif()
      else()
        list(APPEND fixed "${dir}")
      endif()
    endforeach()
    if(changed)
      list(REMOVE_DUPLICATES fixed)
      set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${fixed}")
    endif()
  endforeach()
endfunction()

cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL _navsuite_fix_wheel_include_dirs)

# The other pip-ROS workaround: let ament find the venv's typesupports without sourcing.
include("${CMAKE_CURRENT_LIST_DIR}/ament_prefix_path.cmake")
