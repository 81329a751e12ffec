# Builds examples/blocks_2d (a stream plugin) out of tree against this build, lists its
# parameters, plans both example problems with it (the blocked one must move b1 out of
# the way), compares the adaptive and incremental searches on them, and checks that a
# problem without a plan is reported with its reason.
# Arguments: -DSOURCE=<repo> -DBINARY=<work dir> -DPACKAGE=<cluttertamp build dir> -DCLI=<cluttertamp>
cmake_minimum_required(VERSION 3.22)  # policies of today: quoted arguments are strings
file(REMOVE_RECURSE "${BINARY}")
set(example "${SOURCE}/examples/blocks_2d")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${example}" -B "${BINARY}/build" "-Dcluttertamp_DIR=${PACKAGE}"
                        -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the example failed:\n${out}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${BINARY}/build" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the example failed:\n${out}")
endif()
set(plugins "${BINARY}/build/plugins")

function(run expected_rc)
  execute_process(COMMAND "${CLI}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("$ cluttertamp ${ARGN}\n${out}${err}")
  if(NOT rc EQUAL expected_rc)
    message(FATAL_ERROR "exit code ${rc}, expected ${expected_rc}")
  endif()
  set(out "${out}${err}" PARENT_SCOPE)
endfunction()
function(expect text)
  string(FIND "${out}" "${text}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the output lacks '${text}'")
  endif()
endfunction()

run(0 plugins -v --plugin-path "${plugins}")
expect("blocks_2d")
expect("carry_height")
expect("m: the gripper's tip crosses at least this high")
expect("workspace")

run(0 plan "${example}/tight.yaml" --plugin-path "${plugins}" -o "${BINARY}/tight")
expect("result    SOLVED: 9 steps")
expect("place b1 ")
file(READ "${BINARY}/tight/result.json" json)
string(JSON first_action GET "${json}" plan 0 action)
string(JSON first_argument GET "${json}" plan 0 arguments 0)
string(JSON q0 GET "${json}" plan 0 values q0)
if(NOT first_action STREQUAL "move" OR NOT first_argument STREQUAL "q0" OR NOT q0 MATCHES "^\\[ *-5(\\.0)? *, *6(\\.0)? *\\]$")
  message(FATAL_ERROR "result.json: the first step should move from q0 = [-5, 6]: ${first_action} ${first_argument} ${q0}")
endif()

run(0 plan "${example}/blocked.yaml" --plugin-path "${plugins}" -o "${BINARY}/blocked")
expect("pick b1 p1 ")  # b1 stands in the way in the red region
expect("place b0 ")

run(0 compare "${example}/tight.yaml" "${example}/blocked.yaml" --runs 2 --plugin-path "${plugins}" --json "${BINARY}/compare.json")
file(READ "${BINARY}/compare.json" json)
string(JSON rows LENGTH "${json}")
if(NOT rows EQUAL 4)
  message(FATAL_ERROR "compare.json: ${rows} rows, expected 4 (2 problems x 2 algorithms; pruning needs a scene)")
endif()
foreach(i RANGE 3)
  string(JSON rate GET "${json}" ${i} success_rate)
  if(NOT rate EQUAL 1)
    message(FATAL_ERROR "compare.json row ${i}: success rate ${rate}")
  endif()
endforeach()

# b0 may not go into red: no plan, even optimistically (the incremental search cannot
# tell and runs to its limit, whatever the machine).
file(READ "${example}/tight.pddl" pddl)
string(REPLACE "(Placeable b0 red)" "" pddl "${pddl}")
file(WRITE "${BINARY}/impossible.pddl" "${pddl}")
file(READ "${example}/tight.yaml" yaml)
string(REPLACE "domain: domain.pddl" "domain: ${example}/domain.pddl" yaml "${yaml}")
string(REPLACE "streams: stream.pddl" "streams: ${example}/stream.pddl" yaml "${yaml}")
string(REPLACE "problem: tight.pddl" "problem: impossible.pddl" yaml "${yaml}")
file(WRITE "${BINARY}/impossible.yaml" "${yaml}")
# It ran (exit code 0); with --check-goals, a run unsolved is exit code 1.
run(0 compare "${BINARY}/impossible.yaml" --runs 1 --time-limit 1 --plugin-path "${plugins}")
run(1 compare "${BINARY}/impossible.yaml" --runs 1 --time-limit 1 --plugin-path "${plugins}" --check-goals)
expect("Failed runs:")
expect("blocks-2d-tight, adaptive, all movable: 1x no plan exists: not even with optimistic stream outputs")

# A value for an object the PDDL problem does not have is bad input, located.
file(READ "${BINARY}/impossible.yaml" yaml)
string(REPLACE "      q0: [-5, 6]" "      q0: [-5, 6]\n      qz: [0, 0]" yaml "${yaml}")
string(REPLACE "problem: impossible.pddl" "problem: ${example}/tight.pddl" yaml "${yaml}")
file(WRITE "${BINARY}/stray_value.yaml" "${yaml}")
run(2 plan "${BINARY}/stray_value.yaml" --plugin-path "${plugins}" -o "${BINARY}/stray")
expect("stray_value.yaml:21:11: error: values: 'qz' is not an object of PDDL problem")

# The incremental search's first plan takes detours (a pick and a place of a block only
# to free the hand for the next move); the cost-aware polish takes them away.
file(READ "${example}/blocked.yaml" yaml)
string(REPLACE "domain: domain.pddl" "domain: ${example}/domain.pddl" yaml "${yaml}")
string(REPLACE "streams: stream.pddl" "streams: ${example}/stream.pddl" yaml "${yaml}")
string(REPLACE "problem: blocked.pddl" "problem: ${example}/blocked.pddl" yaml "${yaml}")
foreach(polish IN ITEMS wastar-ff "\"\"")
  string(REPLACE "algorithm: adaptive}" "algorithm: incremental, polish_search: ${polish}}" variant "${yaml}")
  file(WRITE "${BINARY}/incremental.yaml" "${variant}")
  run(0 plan "${BINARY}/incremental.yaml" --plugin-path "${plugins}" -o "${BINARY}/incremental")
  string(REGEX MATCH "SOLVED: ([0-9]+) steps" solved "${out}")
  list(APPEND lengths "${CMAKE_MATCH_1}")
endforeach()
list(GET lengths 0 polished)
list(GET lengths 1 raw)
if(NOT polished EQUAL 9 OR NOT raw GREATER 9)
  message(FATAL_ERROR "incremental plan lengths: ${polished} polished (expected 9), ${raw} without (expected more)")
endif()

# success_cost: below the first plan's cost the adaptive search goes on for cheaper
# plans (within improve_work, counted work: the same plans on any machine) and returns
# the cheapest it found.
foreach(success_cost IN ITEMS "" ", success_cost: 0")
  string(REPLACE "algorithm: adaptive}" "algorithm: adaptive${success_cost}}" variant "${yaml}")
  file(WRITE "${BINARY}/success_cost.yaml" "${variant}")
  run(0 plan "${BINARY}/success_cost.yaml" --plugin-path "${plugins}" -o "${BINARY}/success_cost")
  expect(", cost ")
  file(READ "${BINARY}/success_cost/result.json" json)
  string(JSON cost GET "${json}" cost)
  string(JSON plans GET "${json}" counters plans_found)
  list(APPEND costs "${cost}")
  list(APPEND plan_counts "${plans}")
endforeach()
list(GET costs 0 first_cost)
list(GET costs 1 best_cost)
list(GET plan_counts 0 first_plans)
list(GET plan_counts 1 best_plans)
if(NOT first_plans EQUAL 1 OR NOT best_plans GREATER 1 OR NOT best_cost LESS first_cost)
  message(FATAL_ERROR "success_cost: first plan cost ${first_cost} (${first_plans} found), with success_cost 0 ${best_cost} (${best_plans} found)")
endif()

# Stream options out of range are bad input at their line.
string(REPLACE "algorithm: adaptive}" "algorithm: adaptive, streams: {test-cfree: {p_success: 2}}}" variant "${yaml}")
file(WRITE "${BINARY}/p_success.yaml" "${variant}")
run(2 plan "${BINARY}/p_success.yaml" --plugin-path "${plugins}" -o "${BINARY}/p_success")
expect("p_success.yaml:27:")
expect("stream 'test-cfree': 'p_success' must be a probability in [0, 1], not 2")
