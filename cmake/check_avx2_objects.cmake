# ctest avx2_kernels_share_no_code (cmake/FramequakeAvx2Kernels.cmake):
# every symbol an AVX2 kernel object makes visible to the linker must be
# one of the avx2 forms (its name carries "avx2"). A shared inline function
# (a template instance, say) defined there could be the copy the linker
# keeps for the whole program, and the SSE2 path would then run AVX2 code.
# Usage: cmake -DNM=<nm> -DOBJECTS=<obj>|<obj>... -P check_avx2_objects.cmake
string(REPLACE "|" ";" objects "${OBJECTS}")
list(LENGTH objects n_objects)
if(n_objects EQUAL 0)
  message(FATAL_ERROR "no AVX2 kernel objects given")
endif()
set(failures "")
foreach(object IN LISTS objects)
  execute_process(COMMAND "${NM}" --defined-only "${object}" OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} failed on ${object}")
  endif()
  string(REPLACE "\n" ";" lines "${listing}")
  set(kernels 0)
  foreach(line IN LISTS lines)
    # "<address> <type> <name>"; upper-case types and u, v, w are visible
    # to the linker, the other lower-case ones are local to the object.
    if(NOT line MATCHES "^[0-9a-fA-F]+ ([A-Za-z]) (.+)$")
      continue()
    endif()
    set(type "${CMAKE_MATCH_1}")
    set(name "${CMAKE_MATCH_2}")
    if(NOT type MATCHES "^[A-Zuvw]$")
      continue()
    endif()
    if(name MATCHES "avx2")
      math(EXPR kernels "${kernels} + 1")
    elseif(name STREQUAL "DW.ref.__gxx_personality_v0")
      # A data word holding the address of the C++ exception personality
      # routine (instrumented builds emit it): no instructions of its own.
    else()
      string(APPEND failures "  ${object}: ${type} ${name}\n")
    endif()
  endforeach()
  if(kernels EQUAL 0)
    string(APPEND failures "  ${object}: defines no avx2 kernel at all\n")
  endif()
  message(STATUS "${object}: ${kernels} avx2 symbols, nothing else visible")
endforeach()
if(failures)
  message(FATAL_ERROR "AVX2 kernel objects define code the rest of the program could share:\n${failures}"
                      "Make the function always_inline or move it out of the kernel file.")
endif()
