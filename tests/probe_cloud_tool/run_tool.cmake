# Runs one command line and checks its exit code and output (stdout and stderr together):
#   cmake -DCMD="prog|arg|..." -DEXPECT_RC=N -DEXPECT="regex|regex..." [-DREJECT="regex|..."]
#         -P run_tool.cmake
# (lists joined with '|', as tests/probe_cloud_tool/CMakeLists.txt passes them).
# Every EXPECT regex must match the output, no REJECT regex may. (ctest's PASS_REGULAR_EXPRESSION
# alone would ignore the exit code.)
string(REPLACE "|" ";" CMD "${CMD}")
string(REPLACE "|" ";" EXPECT "${EXPECT}")
string(REPLACE "|" ";" REJECT "${REJECT}")
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
message("${all}")
if(NOT rc STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "exit code ${rc}, expected ${EXPECT_RC}: ${CMD}")
endif()
foreach(re IN LISTS EXPECT)
  if(NOT all MATCHES "${re}")
    message(FATAL_ERROR "output does not match '${re}'")
  endif()
endforeach()
foreach(re IN LISTS REJECT)
  if(all MATCHES "${re}")
    message(FATAL_ERROR "output matches '${re}'")
  endif()
endforeach()
