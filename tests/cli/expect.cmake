# Run one command and check its exit code, its output and the files it should (not) leave.
#
#   cmake -DCOMMAND="prog|arg1|arg2" [-DEXPECT_CODE=N] [-DEXPECT_REGEX=re] [-DREJECT_REGEX=re]
#         [-DEXPECT_FILES="a|b"] [-DREJECT_FILES="c|d"] [-DCLEAN=dir] -P expect.cmake
#
# '|' separates list entries (a ';' does not survive add_test's argument quoting).
# EXPECT_REGEX and REJECT_REGEX apply to stdout and stderr together. CLEAN is removed first.
cmake_minimum_required(VERSION 3.22)

string(REPLACE "|" ";" command "${COMMAND}")
if(DEFINED CLEAN AND NOT CLEAN STREQUAL "")
  file(REMOVE_RECURSE "${CLEAN}")
endif()
execute_process(COMMAND ${command} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
set(failures "")
if(DEFINED EXPECT_CODE AND NOT code STREQUAL EXPECT_CODE)
  string(APPEND failures "exit code ${code}, expected ${EXPECT_CODE}\n")
endif()
if(DEFINED EXPECT_REGEX AND NOT all MATCHES "${EXPECT_REGEX}")
  string(APPEND failures "output does not match '${EXPECT_REGEX}'\n")
endif()
if(DEFINED REJECT_REGEX AND all MATCHES "${REJECT_REGEX}")
  string(APPEND failures "output matches '${REJECT_REGEX}'\n")
endif()
if(DEFINED EXPECT_FILES)
  string(REPLACE "|" ";" files "${EXPECT_FILES}")
  foreach(f ${files})
    if(NOT EXISTS "${f}")
      string(APPEND failures "missing file ${f}\n")
    endif()
  endforeach()
endif()
if(DEFINED REJECT_FILES)
  string(REPLACE "|" ";" files "${REJECT_FILES}")
  foreach(f ${files})
    if(EXISTS "${f}")
      string(APPEND failures "unexpected file ${f}\n")
    endif()
  endforeach()
endif()
if(NOT failures STREQUAL "")
  message(FATAL_ERROR "${COMMAND}\n${failures}--- output ---\n${all}")
endif()
