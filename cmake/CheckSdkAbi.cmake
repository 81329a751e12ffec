# Fails when the plugin SDK (the headers of include/cluttertamp/core/, plugin/ and
# export.hpp) changed without the plugin ABI version changing with it.
#
# The SDK's fingerprint is a SHA-256 of its headers with comments and whitespace taken
# out, so that documentation changes do not count. RECORD holds the ABI version and the
# fingerprint it was raised for; after changing the SDK, raise
# CLUTTERTAMP_PLUGIN_ABI_VERSION in plugin/plugin.hpp and write both into RECORD (the
# failure message prints them).
# Arguments: -DINCLUDE=<repo>/include -DRECORD=<file>
get_filename_component(INCLUDE "${INCLUDE}" ABSOLUTE)
file(GLOB_RECURSE headers RELATIVE "${INCLUDE}" "${INCLUDE}/cluttertamp/core/*.hpp" "${INCLUDE}/cluttertamp/plugin/*.hpp")
list(LENGTH headers count)
if(count LESS 10)
  message(FATAL_ERROR "found ${count} SDK headers under ${INCLUDE}: is that the include directory?")
endif()
list(APPEND headers cluttertamp/export.hpp)
list(SORT headers)
set(sdk "")
foreach(header IN LISTS headers)
  file(READ "${INCLUDE}/${header}" text)
  string(REGEX REPLACE "//[^\n]*" "" text "${text}")
  string(REGEX REPLACE "[ \t\r\n]+" " " text "${text}")
  string(APPEND sdk "${header}: ${text}\n")
endforeach()
string(SHA256 fingerprint "${sdk}")

file(READ "${INCLUDE}/cluttertamp/plugin/plugin.hpp" plugin_hpp)
string(REGEX MATCH "#define CLUTTERTAMP_PLUGIN_ABI_VERSION ([0-9]+)" _ "${plugin_hpp}")
set(abi "${CMAKE_MATCH_1}")

file(STRINGS "${RECORD}" record REGEX "^(abi|sdk) ")
set(recorded_abi "")
set(recorded_sdk "")
foreach(line IN LISTS record)
  if(line MATCHES "^abi ([0-9]+)$")
    set(recorded_abi "${CMAKE_MATCH_1}")
  elseif(line MATCHES "^sdk ([0-9a-f]+)$")
    set(recorded_sdk "${CMAKE_MATCH_1}")
  endif()
endforeach()

if(recorded_sdk STREQUAL fingerprint AND recorded_abi STREQUAL abi)
  message(STATUS "plugin ABI ${abi} matches the SDK")
  return()
endif()
if(NOT recorded_sdk STREQUAL fingerprint AND recorded_abi STREQUAL abi)
  message(FATAL_ERROR "the plugin SDK changed but CLUTTERTAMP_PLUGIN_ABI_VERSION is still ${abi}: plugins built "
                      "against the old SDK would load and break. Raise it in include/cluttertamp/plugin/plugin.hpp "
                      "and write into ${RECORD}:\nabi <the new version>\nsdk ${fingerprint}")
endif()
message(FATAL_ERROR "${RECORD} does not match the SDK: it says abi ${recorded_abi}, sdk ${recorded_sdk}; "
                    "the SDK is ABI ${abi}, fingerprint ${fingerprint}. If the version was raised for this SDK, "
                    "write into ${RECORD}:\nabi ${abi}\nsdk ${fingerprint}")
