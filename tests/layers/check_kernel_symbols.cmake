# Fails when an object of the AVX2 GEMM kernel defines a symbol outside its
# renamed Eigen namespace (pleat_eigen_avx2) and its entry point.
execute_process(COMMAND ${NM} --defined-only -C ${OBJECTS} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${OBJECTS}")
endif()
string(REPLACE "\n" ";" lines "${symbols}")
set(entry_found FALSE)
foreach(line ${lines})
  if(line MATCHES "pleat::nn::kernels::gemm_avx2")
    set(entry_found TRUE)
  elseif(line MATCHES " [a-z] " OR line MATCHES "pleat_eigen_avx2" OR line MATCHES "DW\\.ref\\.__gxx_personality_v0"
         OR line STREQUAL "")
    # local symbols (lower-case type), the renamed Eigen, the EH personality reference
  else()
    message(FATAL_ERROR "the AVX2 kernel exports a symbol the rest of the library may share: ${line}")
  endif()
endforeach()
if(NOT entry_found)
  message(FATAL_ERROR "no pleat::nn::kernels::gemm_avx2 in ${OBJECTS}")
endif()
message(STATUS "AVX2 kernel symbols are private")
