# Fails when a file of src/<layer>/ includes a header of a higher layer.
#   cmake -DSOURCE_DIR=<tree with src/> -DLAYERS=core,io,... -P check_layers.cmake
# LAYERS lists the layers bottom-up; the C boundary (src/capi) sits above them
# all. Includes that do not name a file under src/ (the public header
# capi/pleat.h in include/, generated schema headers, system headers) are not
# layers and pass.
if(NOT SOURCE_DIR OR NOT LAYERS)
  message(FATAL_ERROR "usage: cmake -DSOURCE_DIR=<dir> -DLAYERS=<a,b,...> -P check_layers.cmake")
endif()
string(REPLACE "," ";" order "${LAYERS}")
list(APPEND order capi)
set(violations "")
foreach(layer ${order})
  list(FIND order ${layer} rank)
  file(GLOB files ${SOURCE_DIR}/src/${layer}/*.h ${SOURCE_DIR}/src/${layer}/*.cpp)
  foreach(file ${files})
    file(STRINGS ${file} includes REGEX "^#include \"[a-z_]+/[A-Za-z0-9_.]+\"")
    foreach(line ${includes})
      string(REGEX REPLACE "^#include \"(([a-z_]+)/[A-Za-z0-9_.]+)\".*" "\\1;\\2" parts "${line}")
      list(GET parts 0 header)
      list(GET parts 1 target)
      list(FIND order ${target} target_rank)
      if(target_rank GREATER rank AND EXISTS ${SOURCE_DIR}/src/${header})
        file(RELATIVE_PATH where ${SOURCE_DIR} ${file})
        string(APPEND violations "  ${where} (layer ${layer}) includes ${header} (layer ${target})\n")
      endif()
    endforeach()
  endforeach()
endforeach()
if(violations)
  message(FATAL_ERROR "upward includes (layers bottom-up: ${order}):\n${violations}")
endif()
message(STATUS "layers in order: ${order}")
