# Builds examples/my_grasps out of tree against this build, then loads it by name from
# the example's problem file and asks it for grasps.
# Arguments: -DSOURCE=<repo> -DBINARY=<work dir> -DPACKAGE=<cluttertamp build dir> -DTRY=<example_try_grasps>
file(REMOVE_RECURSE "${BINARY}")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}/examples/my_grasps" -B "${BINARY}"
                        "-Dcluttertamp_DIR=${PACKAGE}" -DCMAKE_BUILD_TYPE=Release
                RESULT_VARIABLE configure OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT configure EQUAL 0)
  message(FATAL_ERROR "configuring the example failed:\n${out}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${BINARY}" RESULT_VARIABLE build OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT build EQUAL 0)
  message(FATAL_ERROR "building the example failed:\n${out}")
endif()
execute_process(COMMAND "${TRY}" "${SOURCE}/examples/my_grasps/problem.yaml" --plugin-path "${BINARY}/plugins" --all
                RESULT_VARIABLE run OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT run EQUAL 0 OR NOT out MATCHES "grasp sampler 'my_grasps'" OR NOT out MATCHES "target: 0 usable, least blocked by"
   OR NOT out MATCHES "\n    -?[0-9]+ deg: [a-z]")
  message(FATAL_ERROR "the example plugin did not load or answer")
endif()
