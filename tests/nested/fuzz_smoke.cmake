# Builds the libFuzzer harnesses with clang in a scratch build and runs each for a few seconds
# from its committed seed corpus with a fixed seed. Any crash, sanitizer report or broken
# property fails the test.
string(REPLACE "," ";" FUZZERS "${FUZZERS}")
file(MAKE_DIRECTORY ${WORK})
# -O1 and line tables only, as the sanitizer tree: the build is most of this test (913 s in CI at
# RelWithDebInfo's -O2 -g, accel.cpp alone over 3 min); the harnesses' few seconds of fuzzing run
# somewhat fewer inputs. The outer build's generator.
if(NOT GEN)
  set(GEN "Unix Makefiles")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${WORK}/build -G ${GEN} -DCMAKE_CXX_COMPILER=${CLANGXX}
                        -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
                        "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DRAYPROOF_FUZZ=ON -DRAYPROOF_BUILD_TESTS=OFF
                        -DRAYPROOF_BUILD_BENCH=OFF -DRAYPROOF_INSTALL=OFF -DRAYPROOF_NESTED_CHECKS=OFF
                        COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/build -j2 --target ${FUZZERS} COMMAND_ERROR_IS_FATAL ANY)
foreach(f ${FUZZERS})
  string(REPLACE "fuzz_" "" corpus ${f})
  # Work on a copy: libFuzzer adds what it finds to the first corpus directory.
  file(REMOVE_RECURSE ${WORK}/corpus/${corpus})
  file(COPY ${SRC}/fuzz/corpus/${corpus} DESTINATION ${WORK}/corpus)
  message(STATUS "fuzzing ${f} for ${SECONDS} s")
  execute_process(COMMAND ${WORK}/build/fuzz/${f} -seed=1 -max_total_time=${SECONDS} -rss_limit_mb=2048
                          -max_len=4096 ${WORK}/corpus/${corpus}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REGEX MATCH "Done [0-9]+ runs[^\n]*" done "${err}")
  message(STATUS "${f}: ${done}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${f} failed (exit ${rc}):\n${err}")
  endif()
endforeach()
