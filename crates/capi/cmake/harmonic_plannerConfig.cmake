# find_package(harmonic_planner) from an install prefix laid out as crates/capi/README.md says:
#   <prefix>/include/harmonic_planner.h and harmonic_planner.hpp
#   <prefix>/lib/libharmonic_planner.so and libharmonic_planner.a
#   <prefix>/lib/cmake/harmonic_planner/harmonic_plannerConfig.cmake (this file)
# Targets: harmonic_planner::harmonic_planner (shared) and harmonic_planner::static.
get_filename_component(_hp_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)

if(NOT TARGET harmonic_planner::harmonic_planner)
  add_library(harmonic_planner::harmonic_planner SHARED IMPORTED)
  set_target_properties(harmonic_planner::harmonic_planner PROPERTIES
    IMPORTED_LOCATION "${_hp_prefix}/lib/libharmonic_planner.so"
    INTERFACE_INCLUDE_DIRECTORIES "${_hp_prefix}/include")
endif()

if(NOT TARGET harmonic_planner::static AND EXISTS "${_hp_prefix}/lib/libharmonic_planner.a")
  add_library(harmonic_planner::static STATIC IMPORTED)
  set_target_properties(harmonic_planner::static PROPERTIES
    IMPORTED_LOCATION "${_hp_prefix}/lib/libharmonic_planner.a"
    INTERFACE_INCLUDE_DIRECTORIES "${_hp_prefix}/include"
    INTERFACE_LINK_LIBRARIES "pthread;dl;m")
endif()

set(harmonic_planner_FOUND TRUE)
unset(_hp_prefix)
