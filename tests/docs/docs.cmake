# The documentation kept honest: docs/cli.md is what the generator writes today, and it names every
# flag `gpsemu --help` and `gpsemu SUBCOMMAND --help` print; docs/ublox.md's tables are generated;
# the pipeline names no protocol, as docs/design.md says. (The other .cmake files here are their
# -P scripts.)
add_test(NAME docs.cli_reference_is_current
         COMMAND ${CMAKE_COMMAND} -DGENERATOR=$<TARGET_FILE:gpsemu-cli-doc>
                 -DDOC=${PROJECT_SOURCE_DIR}/docs/cli.md -DOUT=${CMAKE_CURRENT_BINARY_DIR}/cli.md.generated
                 -P ${CMAKE_CURRENT_LIST_DIR}/cli_doc_current.cmake)
set_tests_properties(docs.cli_reference_is_current PROPERTIES LABELS unit)

add_test(NAME docs.cli_reference_covers_help
         COMMAND ${CMAKE_COMMAND} -DGPSEMU=$<TARGET_FILE:gpsemu> -DDOC=${PROJECT_SOURCE_DIR}/docs/cli.md
                 -P ${CMAKE_CURRENT_LIST_DIR}/cli_doc_covers_help.cmake)
set_tests_properties(docs.cli_reference_covers_help PROPERTIES LABELS e2e)

add_test(NAME docs.ublox_tables_are_current
         COMMAND ${CMAKE_COMMAND} -DGENERATOR=$<TARGET_FILE:gpsemu-ublox-doc>
                 -DDOC=${PROJECT_SOURCE_DIR}/docs/ublox.md -DOUT=${CMAKE_CURRENT_BINARY_DIR}/ublox.md.generated
                 -P ${CMAKE_CURRENT_LIST_DIR}/ublox_doc_current.cmake)
set_tests_properties(docs.ublox_tables_are_current PROPERTIES LABELS unit)

# docs/design.md's "the loop knows no protocol": emulator/pipeline names no ubx (issue 36).
add_test(NAME docs.pipeline_knows_no_protocol
         COMMAND ${CMAKE_COMMAND} -DDIR=${PROJECT_SOURCE_DIR}/emulator/pipeline
                 -P ${CMAKE_CURRENT_LIST_DIR}/pipeline_knows_no_protocol.cmake)
set_tests_properties(docs.pipeline_knows_no_protocol PROPERTIES LABELS unit)

# docs/sky.md's table of the default sky by place is what tools/update-sky-doc writes from this
# build's gpsemu (48 one-epoch runs, a few seconds).
add_test(NAME docs.sky_table_is_current
         COMMAND python3 ${PROJECT_SOURCE_DIR}/tools/update-sky-doc --check
                 --gpsemu $<TARGET_FILE:gpsemu> --doc ${PROJECT_SOURCE_DIR}/docs/sky.md)
set_tests_properties(docs.sky_table_is_current PROPERTIES LABELS e2e)
