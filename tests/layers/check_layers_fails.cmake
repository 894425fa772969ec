# The layer check must catch an upward include: a tree whose core header
# includes a runtime header fails, and the message names the file and both
# layers; the same tree without that line passes.
#   cmake -DCHECK=<check_layers.cmake> -DWORK=<scratch dir> -P check_layers_fails.cmake
file(REMOVE_RECURSE ${WORK})
file(WRITE ${WORK}/src/runtime/instance.h "#pragma once\n#include \"core/mesh.h\"\n")
file(WRITE ${WORK}/src/core/mesh.h "#pragma once\n#include \"capi/pleat.h\"\n#include <vector>\n")
file(WRITE ${WORK}/src/core/geometry.cpp "#include \"core/mesh.h\"\n#include \"runtime/instance.h\"\n")
set(args -DSOURCE_DIR=${WORK} -DLAYERS=core,io,runtime -P ${CHECK})
execute_process(COMMAND ${CMAKE_COMMAND} ${args} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(status EQUAL 0)
  message(FATAL_ERROR "an upward include passed the check:\n${out}")
endif()
if(NOT out MATCHES "src/core/geometry.cpp \\(layer core\\) includes runtime/instance.h \\(layer runtime\\)")
  message(FATAL_ERROR "the check failed without naming the include:\n${out}")
endif()
file(WRITE ${WORK}/src/core/geometry.cpp "#include \"core/mesh.h\"\n")
execute_process(COMMAND ${CMAKE_COMMAND} ${args} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "a tree in order failed the check:\n${out}")
endif()
