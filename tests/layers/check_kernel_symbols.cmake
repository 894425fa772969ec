# Fails when an object of the AVX2 kernel build (src/nn/kernels) defines a
# symbol outside its renamed Eigen namespace (pleat_eigen_avx2) and its entry
# points, or when an entry point is missing.
cmake_policy(SET CMP0057 NEW)  # if(IN_LIST) in script mode
execute_process(COMMAND ${NM} --defined-only -C ${OBJECTS} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${OBJECTS}")
endif()
string(REPLACE "\n" ";" lines "${symbols}")
set(entries gemm_avx2 attention_aggregate_avx2 activate_avx2)
set(found "")
foreach(line ${lines})
  if(line MATCHES "pleat::nn::kernels::([a-z_0-9]+_avx2)\\(")
    list(APPEND found ${CMAKE_MATCH_1})
  elseif(line MATCHES " [a-z] " OR line MATCHES "pleat_eigen_avx2" OR line MATCHES "DW\\.ref\\.__gxx_personality_v0"
         OR line STREQUAL "" OR line MATCHES ":$")
    # local symbols (lower-case type), the renamed Eigen, the EH personality
    # reference, nm's per-object headers
  else()
    message(FATAL_ERROR "the AVX2 kernels export a symbol the rest of the library may share: ${line}")
  endif()
endforeach()
foreach(entry ${entries})
  if(NOT entry IN_LIST found)
    message(FATAL_ERROR "no pleat::nn::kernels::${entry} in ${OBJECTS}")
  endif()
endforeach()
message(STATUS "AVX2 kernel symbols are private: ${found}")
