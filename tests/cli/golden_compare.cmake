# Runs gpsemu with the arguments in ARGS_FILE (one per line) writing to ACTUAL, and compares the
# bytes with EXPECTED; on a difference prints the first differing lines.
file(STRINGS ${ARGS_FILE} args)
execute_process(COMMAND ${GPSEMU} ${args} --output file:${ACTUAL} RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gpsemu exited ${rc}: ${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${EXPECTED} ${ACTUAL} RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  execute_process(COMMAND diff ${EXPECTED} ${ACTUAL} OUTPUT_VARIABLE d)
  string(SUBSTRING "${d}" 0 2000 d)
  message(FATAL_ERROR "output differs from ${EXPECTED}:\n${d}\nIf the change is intended, run tools/update-golden.")
endif()
