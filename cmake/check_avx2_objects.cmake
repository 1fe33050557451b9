# ctest avx2_kernels_share_no_code and avx512vl_kernels_share_no_code
# (cmake/FramequakeAvx2Kernels.cmake), for the objects of one SIMD form:
#  - every symbol such an object makes visible to the linker must be one of
#    that form's kernels (its name carries the form's name, FORM). A shared
#    inline function (a template instance, say) defined there could be the
#    copy the linker keeps for the whole program, and the SSE2 path would
#    then run AVX2 or AVX-512 code;
#  - the object holds no fused multiply-add instruction (vfmadd..., vfmsub...,
#    vfnmadd..., vfnmsub...): a fused operation rounds once where the SSE2
#    form rounds twice, and every form must give the SSE2 form's bits. (The
#    AVX-512VL form is compiled with -mfma, which Eigen requires beside
#    -mavx512f, and -ffp-contract=off.)
# Usage: cmake -DNM=<nm> -DOBJDUMP=<objdump> -DFORM=<avx2|avx512vl>
#              -DOBJECTS=<obj>|<obj>... -P check_avx2_objects.cmake
if(NOT FORM)
  message(FATAL_ERROR "FORM (avx2 or avx512vl) not given")
endif()
string(REPLACE "|" ";" objects "${OBJECTS}")
list(LENGTH objects n_objects)
if(n_objects EQUAL 0)
  message(FATAL_ERROR "no ${FORM} kernel objects given")
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
    # (No form's name contains another's: "avx512vl" holds no "avx2".)
    if(name MATCHES "${FORM}")
      math(EXPR kernels "${kernels} + 1")
    elseif(name STREQUAL "DW.ref.__gxx_personality_v0")
      # A data word holding the address of the C++ exception personality
      # routine (instrumented builds emit it): no instructions of its own.
    else()
      string(APPEND failures "  ${object}: ${type} ${name}\n")
    endif()
  endforeach()
  if(kernels EQUAL 0)
    string(APPEND failures "  ${object}: defines no ${FORM} kernel at all\n")
  endif()
  set(fused 0)
  if(OBJDUMP)
    execute_process(COMMAND "${OBJDUMP}" -d --no-show-raw-insn "${object}" OUTPUT_VARIABLE code RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${OBJDUMP} failed on ${object}")
    endif()
    string(REGEX MATCHALL "\tvfn?m(add|sub)[a-z0-9]*" fused_list "${code}")
    list(LENGTH fused_list fused)
    if(fused GREATER 0)
      list(GET fused_list 0 first_fused)
      string(STRIP "${first_fused}" first_fused)
      string(APPEND failures "  ${object}: ${fused} fused multiply-add instructions (the first: ${first_fused})\n")
    endif()
  else()
    message(FATAL_ERROR "OBJDUMP not given: the fused multiply-add check cannot run")
  endif()
  message(STATUS "${object}: ${kernels} ${FORM} symbols, nothing else visible, ${fused} fused multiply-adds")
endforeach()
if(failures)
  message(FATAL_ERROR "${FORM} kernel objects define code the rest of the program could share, "
                      "or round differently from the SSE2 form:\n${failures}"
                      "Make the function always_inline or move it out of the kernel file; keep FMA out.")
endif()
