# Installs rayproof's header-only core (nothing compiled: no tools, no certified library) into a
# scratch prefix, then configures, builds and runs the consumer project against it with
# find_package(rayproof).
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${WORK}/build -DRAYPROOF_BUILD_TOOLS=OFF -DRAYPROOF_BUILD_CERTIFIED=OFF
                        -DRAYPROOF_BUILD_TESTS=OFF -DRAYPROOF_BUILD_BENCH=OFF -DRAYPROOF_INSTALL=ON
                        -DCMAKE_INSTALL_PREFIX=${WORK}/prefix COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${WORK}/build COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC}/tests/consumer -B ${WORK}/consumer
                        -DCMAKE_PREFIX_PATH=${WORK}/prefix COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/consumer COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${WORK}/consumer/consumer COMMAND_ERROR_IS_FATAL ANY)
