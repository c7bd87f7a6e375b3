# Builds the tree with AddressSanitizer and UndefinedBehaviorSanitizer in a scratch build and runs
# its test suite there (the nested checks themselves are not repeated).
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${WORK} -DCMAKE_BUILD_TYPE=RelWithDebInfo
                        -DRAYPROOF_SANITIZE=ON -DRAYPROOF_BUILD_BENCH=OFF -DRAYPROOF_INSTALL=OFF
                        -DRAYPROOF_NESTED_CHECKS=OFF COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK} -j2 COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --test-dir ${WORK} --output-on-failure -j2 -E install_consumer
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the sanitizer build's tests failed")
endif()
