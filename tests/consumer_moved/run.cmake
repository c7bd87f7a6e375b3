# The headers that moved still work from an installed package: `cmake --install BUILD` (already built,
# nothing rebuilt) into WORK/prefix, then the consumer of this folder, written against the old paths,
# is configured, built and run against it. Each old header must print its deprecation message, which
# names the new path, while the program builds and passes.
cmake_minimum_required(VERSION 3.20)
foreach(v SRC BUILD WORK CXX)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run.cmake needs -D${v}=...")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
include(${CMAKE_CURRENT_LIST_DIR}/../consumer_run.cmake)
run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix --component rayproof)
run(${CMAKE_COMMAND} -S ${SRC}/tests/consumer_moved -B ${WORK}/consumer -DCMAKE_PREFIX_PATH=${WORK}/prefix
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE= -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE)
run(${CMAKE_COMMAND} --build ${WORK}/consumer)
set(build_out "${run_log}")
set(moved "certified certified/intersect" "check verify/check" "contains scene/contains" "exact verify/exact"
          "gtest verify/gtest" "mesh_caster scene/mesh_caster")
foreach(m IN LISTS moved)
  separate_arguments(m)
  list(GET m 0 old)
  list(GET m 1 new)
  if(NOT build_out MATCHES "rayproof/${old}\\.h is deprecated: include rayproof/${new}\\.h instead")
    message(FATAL_ERROR "building against rayproof/${old}.h printed no deprecation message naming rayproof/${new}.h:\n${build_out}")
  endif()
endforeach()
if(NOT build_out MATCHES "rayproof::ClosedMesh is now rayproof::ExactMesh")
  message(FATAL_ERROR "ClosedMesh, the earlier name of ExactMesh, printed no deprecation message:\n${build_out}")
endif()
message(STATUS "the six moved headers and the renamed ClosedMesh build, each with its deprecation message")
run(${WORK}/consumer/consumer_moved)
message(STATUS "${run_out}")
