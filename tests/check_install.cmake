# install the build into a temporary prefix, then configure, build and run a program outside
# the tree against it (tests/install_consumer): find_package(camopt COMPONENTS core) and
# camopt::core alone, and the design-in-code example against the whole package.
# -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DCONSUMER_FLAGS=... (compile and link flags)
file(REMOVE_RECURSE ${WORK_DIR})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install_consumer -B ${WORK_DIR}/build -G Ninja
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DEXAMPLE_DIR=${SOURCE_DIR}/examples
    "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/core_only)
message(STATUS "${last_output}")
run(${WORK_DIR}/build/design_in_code)
if(NOT last_output MATCHES "lift at 180 deg 8\\.000000000 mm")
  message(FATAL_ERROR "design_in_code against the installed package printed: ${last_output}")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
message(STATUS "installed package found and linked")
