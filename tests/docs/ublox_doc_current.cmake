# Fails when docs/ublox.md's generated blocks differ from what gpsemu-ublox-doc writes from the UBX
# tables now (a message, layout or key changed without regenerating, or a block edited by hand).
# Arguments: GENERATOR (the gpsemu-ublox-doc binary), DOC (docs/ublox.md), OUT (a scratch file).
execute_process(COMMAND ${GENERATOR} ${DOC} ${OUT} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gpsemu-ublox-doc failed (${rc}): ${err}")
endif()
file(READ ${OUT} generated)
file(READ ${DOC} checked_in)
if(NOT generated STREQUAL checked_in)
  execute_process(COMMAND diff -u ${DOC} ${OUT} OUTPUT_VARIABLE difference)
  message(FATAL_ERROR "docs/ublox.md is stale (its tables differ from emulator/ubx's): "
                      "run tools/update-ublox-doc and commit docs/ublox.md\n${difference}")
endif()
foreach(block messages payloads keys)
  string(FIND "${checked_in}" "<!-- generated: ${block} -->" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "docs/ublox.md has no generated block ${block}")
  endif()
endforeach()
message(STATUS "docs/ublox.md's tables are current")
