# stratum_add_plugin(<target> SOURCES <files...> PROVIDES <kind>:<name> ... [OUTPUT_DIRECTORY <dir>] [NO_INSTALL])
#
# Builds a plugin as a shared module and writes beside it a manifest
# "<target>.plugin" listing the factories it provides, one "<kind> <name>" per
# line. Stratum reads manifests to decide which libraries a scene needs and opens
# only those (`stratum fit` likewise opens only the library of its target). <kind> is one of
# material, element, contact_law, solver, stage_action, mesh_generator, calibration.
function(stratum_add_plugin target)
  cmake_parse_arguments(ARG "NO_INSTALL" "OUTPUT_DIRECTORY" "SOURCES;PROVIDES" ${ARGN})
  if(NOT ARG_PROVIDES)
    message(FATAL_ERROR "stratum_add_plugin(${target}): PROVIDES is required")
  endif()
  if(NOT ARG_OUTPUT_DIRECTORY)
    if(DEFINED STRATUM_PLUGIN_OUTPUT_DIR)
      set(ARG_OUTPUT_DIRECTORY "${STRATUM_PLUGIN_OUTPUT_DIR}")
    else()
      set(ARG_OUTPUT_DIRECTORY "${CMAKE_CURRENT_BINARY_DIR}")
    endif()
  endif()
  add_library(${target} MODULE ${ARG_SOURCES})
  if(TARGET stratum_framework)
    target_link_libraries(${target} PRIVATE stratum_framework)
  else()
    target_link_libraries(${target} PRIVATE stratum::framework)
  endif()
  set_target_properties(${target} PROPERTIES PREFIX "" OUTPUT_NAME "${target}"
    LIBRARY_OUTPUT_DIRECTORY "${ARG_OUTPUT_DIRECTORY}" CXX_VISIBILITY_PRESET hidden)
  set(manifest "")
  foreach(entry IN LISTS ARG_PROVIDES)
    string(REPLACE ":" " " line "${entry}")
    string(APPEND manifest "${line}\n")
  endforeach()
  file(WRITE "${ARG_OUTPUT_DIRECTORY}/${target}.plugin" "${manifest}")
  # The project's own plugins are listed so that the test program can depend on all of them.
  if(NOT ARG_NO_INSTALL)
    set_property(GLOBAL APPEND PROPERTY STRATUM_PLUGIN_TARGETS ${target})
  endif()
  if(NOT ARG_NO_INSTALL AND DEFINED STRATUM_PLUGIN_INSTALL_DIR)
    install(TARGETS ${target} LIBRARY DESTINATION "${STRATUM_PLUGIN_INSTALL_DIR}")
    install(FILES "${ARG_OUTPUT_DIRECTORY}/${target}.plugin" DESTINATION "${STRATUM_PLUGIN_INSTALL_DIR}")
  endif()
endfunction()
