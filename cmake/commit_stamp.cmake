# Run at every build (cmake -P, engine/io/CMakeLists.txt): writes OUT, the commit of the sources
# being built, for every result file's provenance. "-dirty" follows it when tracked files differ
# from that commit; "unknown" when SOURCE_DIR is not the top of a git work tree (a copy of the
# sources, even one placed inside another repository). OUT is rewritten only when that changes,
# so a build recompiles the one file that includes it only then.
set(commit "unknown")
file(REAL_PATH "${SOURCE_DIR}" source)
execute_process(COMMAND git rev-parse --show-toplevel --short=12 HEAD
                WORKING_DIRECTORY "${SOURCE_DIR}" OUTPUT_VARIABLE lines
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_VARIABLE error RESULT_VARIABLE status)
if(status EQUAL 0)
  string(REPLACE "\n" ";" lines "${lines}")
  list(GET lines 0 top)
  list(GET lines 1 head)
  file(REAL_PATH "${top}" top)
  if(top STREQUAL source)
    set(commit "${head}")
    execute_process(COMMAND git diff --quiet HEAD -- WORKING_DIRECTORY "${SOURCE_DIR}"
                    RESULT_VARIABLE changed OUTPUT_QUIET ERROR_QUIET)
    if(NOT changed EQUAL 0)
      string(APPEND commit "-dirty")
    endif()
  endif()
elseif(EXISTS "${SOURCE_DIR}/.git")
  # A checkout git will not read (another user's, "dubious ownership"; or no git): say so, as
  # every result file of this build will carry "unknown".
  string(STRIP "${error}" error)
  message(WARNING "plastivox: the commit of ${SOURCE_DIR} is unknown to this build's results "
                  "(git: ${error})")
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
