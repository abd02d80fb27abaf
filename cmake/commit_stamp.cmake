# Run at every build (cmake -P, engine/io/CMakeLists.txt): writes OUT, the commit of the sources
# being built, for every result file's provenance. "-dirty" follows it when tracked files differ
# from that commit; "unknown" outside a git work tree (a copy of the sources). OUT is rewritten
# only when that changes, so a build recompiles the one file that includes it only then.
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY "${SOURCE_DIR}"
                OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                RESULT_VARIABLE status)
if(NOT status EQUAL 0 OR commit STREQUAL "")
  set(commit "unknown")
else()
  execute_process(COMMAND git diff --quiet HEAD -- WORKING_DIRECTORY "${SOURCE_DIR}"
                  RESULT_VARIABLE changed OUTPUT_QUIET ERROR_QUIET)
  if(NOT changed EQUAL 0)
    string(APPEND commit "-dirty")
  endif()
endif()
string(CONCAT text "// Written at every build by cmake/commit_stamp.cmake: the commit of the sources built.\n"
         "#pragma once\n#define PLASTIVOX_BUILD_GIT_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
