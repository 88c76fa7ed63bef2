# Fails when docs/cli.md differs from what gpsemu-cli-doc writes now (an option or subcommand was
# added or changed without regenerating it, or the file was edited by hand).
# Arguments: GENERATOR (the gpsemu-cli-doc binary), DOC (docs/cli.md), OUT (a scratch file).
execute_process(COMMAND ${GENERATOR} ${OUT} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gpsemu-cli-doc failed (${rc}): ${err}")
endif()
if(NOT EXISTS ${DOC})
  message(FATAL_ERROR "${DOC} is missing: run tools/update-cli-doc and commit docs/cli.md")
endif()
file(READ ${OUT} generated)
file(READ ${DOC} checked_in)
if(NOT generated STREQUAL checked_in)
  execute_process(COMMAND diff -u ${DOC} ${OUT} OUTPUT_VARIABLE difference)
  message(FATAL_ERROR "docs/cli.md is stale (it differs from the command line gpsemu parses): "
                      "run tools/update-cli-doc and commit docs/cli.md\n${difference}")
endif()
message(STATUS "docs/cli.md is current")
