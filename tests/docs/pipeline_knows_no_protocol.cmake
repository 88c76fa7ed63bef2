# Fails when a file of emulator/pipeline names the u-blox protocol ("ubx" in any case: an include
# of emulator/ubx/, a ubx:: type, a UBX message): docs/design.md says the loop knows no protocol,
# it sees the receiver's through protocol::ReceiverProtocol (emulator/protocol/), and
# protocol/registry.cpp is the one place that chooses one.
# Arguments: DIR (emulator/pipeline).
file(GLOB_RECURSE sources LIST_DIRECTORIES false ${DIR}/*)
set(found "")
foreach(source ${sources})
  file(STRINGS ${source} lines REGEX "[uU][bB][xX]")
  foreach(line ${lines})
    string(APPEND found "\n${source}: ${line}")
  endforeach()
endforeach()
list(LENGTH sources count)
if(count EQUAL 0)
  message(FATAL_ERROR "no files in ${DIR}")
endif()
if(NOT found STREQUAL "")
  message(FATAL_ERROR "emulator/pipeline names the u-blox protocol (put it behind protocol::ReceiverProtocol, "
                      "emulator/protocol/):${found}")
endif()
message(STATUS "the ${count} files of emulator/pipeline name no ubx")
