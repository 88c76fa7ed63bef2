# A hand edit of a profile fails both checks of tools/update-profiles: a copy of data/profiles with
# one number of ublox-neo-m9n.toml changed (its composite jitter) is refused by --check-digests and
# by --check (regenerated from its log). Arguments: TOOL, GPSEMU, PROFILES (data/profiles), COPY (a scratch directory).
file(REMOVE_RECURSE ${COPY})
file(MAKE_DIRECTORY ${COPY})
file(GLOB files ${PROFILES}/*.toml)
file(COPY ${files} DESTINATION ${COPY})
file(READ ${COPY}/ublox-neo-m9n.toml text)
string(REGEX REPLACE "\ncomposite-jitter = \"[0-9.e-]+," "\ncomposite-jitter = \"0.5," edited "${text}")
if(edited STREQUAL text)
  message(FATAL_ERROR "ublox-neo-m9n.toml has no composite-jitter line to edit: change this test with the profile")
endif()
file(WRITE ${COPY}/ublox-neo-m9n.toml "${edited}")
execute_process(COMMAND python3 ${TOOL} --dir ${COPY} --check-digests RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT err MATCHES "ublox-neo-m9n.toml: edited by hand")
  message(FATAL_ERROR "--check-digests passed an edited profile (${rc}): ${err}")
endif()
execute_process(COMMAND python3 ${TOOL} --dir ${COPY} --gpsemu ${GPSEMU} --check --only ublox-neo-m9n
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(rc EQUAL 0 OR NOT err MATCHES "ublox-neo-m9n.toml is stale" OR NOT err MATCHES "composite-jitter")
  message(FATAL_ERROR "--check passed an edited profile (${rc}): ${err}")
endif()
message(STATUS "an edited profile is refused by --check-digests and by --check")
