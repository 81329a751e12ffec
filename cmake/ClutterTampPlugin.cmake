# cluttertamp_add_plugin(NAME SOURCES... [LINK targets...] [OUTPUT_DIRECTORY dir] [NO_INSTALL])
#
# Builds one plugin as a MODULE library with hidden visibility into the plugin
# directory the registry searches by default (lib/cluttertamp/plugins in the build
# tree and in the install prefix). Only symbols exported with the
# CLUTTERTAMP_EXPORT_* macros are visible to the registry. Inside the cluttertamp
# build, plugins are installed beside libcluttertamp unless NO_INSTALL is given.
function(cluttertamp_add_plugin name)
  cmake_parse_arguments(ARG "NO_INSTALL" "OUTPUT_DIRECTORY" "SOURCES;LINK" ${ARGN})
  add_library(${name} MODULE ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE cluttertamp::cluttertamp ${ARG_LINK})
  if(NOT ARG_OUTPUT_DIRECTORY)
    set(ARG_OUTPUT_DIRECTORY "${CLUTTERTAMP_PLUGIN_OUTPUT_DIR}")
  endif()
  set_target_properties(${name} PROPERTIES
    PREFIX "lib"
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    LIBRARY_OUTPUT_DIRECTORY "${ARG_OUTPUT_DIRECTORY}")
  if(CLUTTERTAMP_PLUGIN_SUBDIR AND NOT ARG_NO_INSTALL)
    install(TARGETS ${name} LIBRARY DESTINATION "${CLUTTERTAMP_PLUGIN_SUBDIR}")
  endif()
endfunction()
