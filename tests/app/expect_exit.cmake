# cmake -DCOMMAND="prog|arg|..." -DEXIT_CODE=N [-DSTDERR_REGEX=RE] -P expect_exit.cmake
# Runs the command and fails unless it exits with EXIT_CODE (a crash reports a signal name
# instead of a number, so it fails too) and, if given, its stderr matches STDERR_REGEX.
string(REPLACE "|" ";" command "${COMMAND}")
execute_process(COMMAND ${command} RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE error
                TIMEOUT 60)
if(NOT "${result}" STREQUAL "${EXIT_CODE}")
  message(FATAL_ERROR "expected exit code ${EXIT_CODE}, got \"${result}\"\nstdout:\n${output}\nstderr:\n${error}")
endif()
if(DEFINED STDERR_REGEX AND NOT error MATCHES "${STDERR_REGEX}")
  message(FATAL_ERROR "stderr does not match \"${STDERR_REGEX}\":\n${error}")
endif()
message(STATUS "exit code ${result} as expected\n${error}")
