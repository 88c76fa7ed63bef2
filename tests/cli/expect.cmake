# Runs one command and checks its exit status and output (CTest's PASS_REGULAR_EXPRESSION and
# WILL_FAIL cannot check an exact status). -DCMD=arg|arg|... -DRC=N -DREGEX=... [-DNOT_REGEX=...]
string(REPLACE "|" ";" argv "${CMD}")
execute_process(COMMAND ${argv} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
set(all "${out}${err}")
if(NOT rc STREQUAL "${RC}")
  message(FATAL_ERROR "exit status ${rc}, expected ${RC}\n--- output ---\n${all}")
endif()
if(DEFINED REGEX AND NOT all MATCHES "${REGEX}")
  message(FATAL_ERROR "output does not match '${REGEX}'\n--- output ---\n${all}")
endif()
if(DEFINED NOT_REGEX AND NOT_REGEX AND all MATCHES "${NOT_REGEX}")
  message(FATAL_ERROR "output matches '${NOT_REGEX}' and should not\n--- output ---\n${all}")
endif()
