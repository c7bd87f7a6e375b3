# run(COMMAND...): runs it, stops the script with its output when it fails; run_out is its standard
# output, run_log its standard output and error together. For the consumer scripts (consumer_all,
# consumer_moved).
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}\n${err}")
  endif()
  set(run_out "${out}" PARENT_SCOPE)
  set(run_log "${out}${err}" PARENT_SCOPE)
endfunction()
