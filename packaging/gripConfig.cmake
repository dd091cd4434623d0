# gripConfig.cmake - the grip CMake package (installed by `make install`).
#
#   find_package(grip 0.1 CONFIG REQUIRED COMPONENTS float)   # or fixed
#   target_link_libraries(app PRIVATE grip::float)
#
# Components and imported targets (docs/porting.md, "Consuming with CMake"):
#   float   grip::float  static libgrip-float.a, GRIP_ARITH_FIXED=0, links libm
#   fixed   grip::fixed  static libgrip-fixed.a, GRIP_ARITH_FIXED=1
#   host only: grip::float_shared, grip::fixed_shared (libgrip-*.so)
# Each carries the include directory and the GRIP_ARITH_FIXED definition, so
# a consumer's view of the headers matches the library. Link one arithmetic
# per target: the two definitions contradict each other.
#
# Which library: GRIP_TARGET = host (the default when not cross-compiling),
# m4f (Cortex-M4F, float) or m0p (Cortex-M0+, fixed). The toolchain files in
# <prefix>/share/grip/cmake set it; with a toolchain file of your own, set
# it before find_package (-DGRIP_TARGET=m4f). Each is installed by
# `make install TARGET=...` into the same prefix.

get_filename_component(_grip_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)

if(DEFINED GRIP_TARGET AND NOT "${GRIP_TARGET}" STREQUAL "")
  set(_grip_target "${GRIP_TARGET}")
elseif(CMAKE_CROSSCOMPILING)
  set(grip_FOUND FALSE)
  set(grip_NOT_FOUND_MESSAGE "cross-compiling: set GRIP_TARGET to the grip library to use (m4f or m0p); the toolchain files in ${_grip_prefix}/share/grip/cmake set it")
  return()
else()
  set(_grip_target host)
endif()

set(_grip_targets_file "${CMAKE_CURRENT_LIST_DIR}/grip-${_grip_target}-targets.cmake")
if(NOT EXISTS "${_grip_targets_file}")
  set(grip_FOUND FALSE)
  set(grip_NOT_FOUND_MESSAGE "grip has no '${_grip_target}' libraries in ${_grip_prefix} (install them: make install TARGET=${_grip_target} PREFIX=...)")
  return()
endif()

# Sets _grip_components, _grip_targets_version, may set _grip_error.
unset(_grip_error)
include("${_grip_targets_file}")
if(DEFINED _grip_error)
  set(grip_FOUND FALSE)
  set(grip_NOT_FOUND_MESSAGE "${_grip_error}")
  return()
endif()
if(NOT "${_grip_targets_version}" STREQUAL "${grip_VERSION}" AND DEFINED grip_VERSION)
  set(grip_FOUND FALSE)
  set(grip_NOT_FOUND_MESSAGE "the '${_grip_target}' libraries in ${_grip_prefix} are version ${_grip_targets_version}, the package ${grip_VERSION}: reinstall one of them")
  return()
endif()

set(grip_TARGET "${_grip_target}")
set(grip_COMPONENTS ${_grip_components})
set(grip_INCLUDE_DIRS "${_grip_prefix}/include")
foreach(_grip_c IN LISTS _grip_components)
  set(grip_${_grip_c}_FOUND TRUE)
endforeach()
foreach(_grip_c IN LISTS grip_FIND_COMPONENTS)
  if(NOT _grip_c IN_LIST _grip_components)
    set(grip_${_grip_c}_FOUND FALSE)
    if(grip_FIND_REQUIRED_${_grip_c})
      set(grip_FOUND FALSE)
      set(grip_NOT_FOUND_MESSAGE "component '${_grip_c}' is not available for GRIP_TARGET=${_grip_target} (available: ${_grip_components})")
    endif()
  endif()
endforeach()
unset(_grip_c)
unset(_grip_targets_file)
