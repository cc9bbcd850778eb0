# marsyn_add_plugin(<target> SOURCES <src>... [LIBRARIES <lib>...])
#
# Builds a marsyn plugin: a MODULE library linking only marsyn::interfaces, with hidden symbols
# (the one entry point is exported explicitly), placed where `marsyn` looks for plugins. Used by
# the project itself and, through find_package(marsyn), by out-of-tree plugins.
function(marsyn_add_plugin target)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES" ${ARGN})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE marsyn::interfaces ${ARG_LIBRARIES})
  target_compile_definitions(${target} PRIVATE MARSYN_PLUGIN_LIBRARY_NAME="${target}")
  set_target_properties(${target} PROPERTIES
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    PREFIX "lib")
  if(MARSYN_PLUGIN_OUTPUT_DIR)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${MARSYN_PLUGIN_OUTPUT_DIR})
  endif()
  if(MARSYN_PLUGIN_INSTALL_DIR)
    install(TARGETS ${target} LIBRARY DESTINATION ${MARSYN_PLUGIN_INSTALL_DIR})
  endif()
endfunction()
