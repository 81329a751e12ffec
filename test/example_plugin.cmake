# Installs the plugin SDK alone (cmake --install --component sdk: the core library, the
# headers of core/ and plugin/), builds examples/my_grasps out of tree against it, then
# loads the plugin by name from the example's problem file and asks it for grasps.
# Arguments: -DSOURCE=<repo> -DBINARY=<work dir> -DPACKAGE=<cluttertamp build dir> -DTRY=<example_try_grasps>
file(REMOVE_RECURSE "${BINARY}")
set(sdk "${BINARY}/sdk")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${PACKAGE}" --component sdk --prefix "${sdk}"
                RESULT_VARIABLE installed OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT installed EQUAL 0)
  message(FATAL_ERROR "installing the SDK failed:\n${out}")
endif()
file(GLOB sdk_headers RELATIVE "${sdk}/include/cluttertamp" "${sdk}/include/cluttertamp/*")
list(SORT sdk_headers)
if(NOT sdk_headers STREQUAL "core;export.hpp;plugin")
  message(FATAL_ERROR "the SDK holds more or less than core/, plugin/ and export.hpp: ${sdk_headers}")
endif()
file(GLOB_RECURSE sdk_libraries "${sdk}/*.so")
foreach(library IN LISTS sdk_libraries)
  if(NOT library MATCHES "libcluttertamp_core\\.so$")
    message(FATAL_ERROR "the SDK installs a library beside the core's: ${library}")
  endif()
endforeach()
file(GLOB sdk_config "${sdk}/lib*/cmake/cluttertamp")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}/examples/my_grasps" -B "${BINARY}/build"
                        "-Dcluttertamp_DIR=${sdk_config}" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
                RESULT_VARIABLE configure OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT configure EQUAL 0)
  message(FATAL_ERROR "configuring the example failed:\n${out}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${BINARY}/build" RESULT_VARIABLE build OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT build EQUAL 0)
  message(FATAL_ERROR "building the example failed:\n${out}")
endif()
execute_process(COMMAND "${TRY}" "${SOURCE}/examples/my_grasps/problem.yaml" --plugin-path "${BINARY}/build/plugins" --all
                RESULT_VARIABLE run OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT run EQUAL 0 OR NOT out MATCHES "grasp sampler 'my_grasps'" OR NOT out MATCHES "target: 0 usable, least blocked by"
   OR NOT out MATCHES "\n    -?[0-9]+ deg: [a-z]")
  message(FATAL_ERROR "the example plugin did not load or answer")
endif()
