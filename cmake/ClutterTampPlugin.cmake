# cluttertamp_add_plugin(NAME SOURCES... [LINK targets...] [OUTPUT_DIRECTORY dir] [NO_INSTALL]
#                        [ALLOW_UNDEFINED])
#
# Builds one plugin as a MODULE library with hidden visibility into the plugin
# directory the registry searches by default (lib/cluttertamp/plugins in the build
# tree and in the install prefix), linked to every layer of cluttertamp (to
# cluttertamp::core alone where only the plugin SDK is installed). Only symbols exported with the
# CLUTTERTAMP_EXPORT_* macros are visible to the registry. Inside the cluttertamp
# build, plugins are installed beside libcluttertamp unless NO_INSTALL is given.
function(cluttertamp_add_plugin name)
  cmake_parse_arguments(ARG "NO_INSTALL;ALLOW_UNDEFINED" "OUTPUT_DIRECTORY" "SOURCES;LINK" ${ARGN})
  add_library(${name} MODULE ${ARG_SOURCES})
  if(TARGET cluttertamp::cluttertamp)
    target_link_libraries(${name} PRIVATE cluttertamp::cluttertamp ${ARG_LINK})
  else()  # the plugin SDK alone
    target_link_libraries(${name} PRIVATE cluttertamp::core ${ARG_LINK})
  endif()
  if(NOT ARG_OUTPUT_DIRECTORY)
    set(ARG_OUTPUT_DIRECTORY "${CLUTTERTAMP_PLUGIN_OUTPUT_DIR}")
  endif()
  # Every symbol resolved at link time: a plugin that needs more than it links fails
  # to build, not to load (and one built against the SDK alone proves it needs no more).
  # ALLOW_UNDEFINED is for the tests' plugin that must fail to load.
  if(NOT ARG_ALLOW_UNDEFINED AND (NOT DEFINED CLUTTERTAMP_NO_UNDEFINED OR CLUTTERTAMP_NO_UNDEFINED))
    target_link_options(${name} PRIVATE "LINKER:--no-undefined")
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
