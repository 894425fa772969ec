# Compares the ABI of include/capi/pleat.h with the committed baseline
# (pleat_abi.xml) using libabigail's abidiff. The header is compiled into a
# probe library with debug information (abi_probe.c); abidw records its types.
#
#   MODE=check     the real header must match the baseline
#   MODE=reorder   a copy with two table entries swapped must NOT match:
#                  proves the check sees a broken layout
#   MODE=baseline  rewrites pleat_abi.xml from the real header (after a
#                  deliberate, compatible change: docs/c_api.md)
# Inputs: CC, ABIDIFF, ABIDW, SOURCE_DIR (repository root), WORK (scratch dir).
cmake_minimum_required(VERSION 3.16)
foreach(tool CC ABIDIFF ABIDW)
  if(NOT ${tool} OR ${tool} MATCHES "NOTFOUND$")
    message(FATAL_ERROR "${tool} not found: scripts/setup.sh installs abigail-tools (abidiff, abidw)")
  endif()
endforeach()
set(header ${SOURCE_DIR}/include/capi/pleat.h)
set(baseline_xml ${SOURCE_DIR}/tests/abi/pleat_abi.xml)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/include/capi)

file(READ ${header} text)
if(MODE STREQUAL "reorder")
  # Swap two table entries (each a declaration up to its ';', names and all).
  string(REGEX MATCH "  [^\n;]*\\(\\*garment_destroy\\)[^;]*;" a "${text}")
  string(REGEX MATCH "  [^\n;]*\\(\\*garment_get_report\\)[^;]*;" b "${text}")
  if(NOT a OR NOT b)
    message(FATAL_ERROR "check_abi: the table entries to swap are no longer in ${header}")
  endif()
  string(REPLACE "${a}" "@A@" text "${text}")
  string(REPLACE "${b}" "${a}" text "${text}")
  string(REPLACE "@A@" "${b}" text "${text}")
endif()
file(WRITE ${WORK}/include/capi/pleat.h "${text}")

# The prefix maps keep the checkout's path out of the baseline.
execute_process(COMMAND ${CC} -g -O0 -shared -fPIC -fvisibility=hidden -I${WORK}/include
                        -fdebug-prefix-map=${SOURCE_DIR}=. -fdebug-prefix-map=${WORK}=.
                        ${SOURCE_DIR}/tests/abi/abi_probe.c -o ${WORK}/probe.so
                WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "check_abi: compiling the probe failed:\n${err}")
endif()

if(MODE STREQUAL "baseline")
  execute_process(COMMAND ${ABIDW} --no-show-locs --no-corpus-path --out-file ${baseline_xml} ${WORK}/probe.so
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "check_abi: abidw failed")
  endif()
  message(STATUS "wrote ${baseline_xml}")
  return()
endif()

# abidiff's status is a bit field: 1 error, 2 usage, 4 ABI change,
# 8 incompatible change (a removed function or variable).
execute_process(COMMAND ${ABIDIFF} ${baseline_xml} ${WORK}/probe.so RESULT_VARIABLE rc OUTPUT_VARIABLE report)
math(EXPR tool_error "${rc} & 3")
if(NOT tool_error EQUAL 0)
  message(FATAL_ERROR "check_abi: abidiff failed (status ${rc}):\n${report}")
endif()
if(MODE STREQUAL "check" AND NOT rc EQUAL 0)
  message(FATAL_ERROR "the ABI of ${header} differs from ${baseline_xml} (abidiff status ${rc}). "
                      "If the change is a deliberate append, see docs/c_api.md, 'Changing the ABI'.\n${report}")
endif()
if(MODE STREQUAL "reorder")
  if(rc EQUAL 0 OR NOT report MATCHES "garment_destroy' offset changed")
    message(FATAL_ERROR "check_abi: swapping two table entries went unnoticed (status ${rc}):\n${report}")
  endif()
endif()
message(STATUS "check_abi ${MODE}: abidiff status ${rc}")
