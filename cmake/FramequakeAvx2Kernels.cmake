# Wider forms of the SIMD lane kernels (dem_core/lanes.h, dem_core/lane_isa.h):
#   avx2      option FQ_AVX2_KERNELS, compiled with -mavx2;
#   avx512vl  option FQ_AVX512VL_KERNELS, the same 256-bit code compiled
#             with -mavx512f -mavx512vl, whose EVEX encoding gives the
#             kernels 32 vector registers instead of 16 (fewer spills to the
#             stack; docs/performance_history.md, change 37). No 512-bit register
#             and no new operation: the lanes stay four doubles wide.
#
# fq_simd_kernel_sources(<target> AVX2 <source>... AVX512VL <source>...)
# compiles each form's sources into an object library <target>_<form>
# linked into <target>, and tells every user of <target>
# FQ_HAVE_AVX2_KERNELS and FQ_HAVE_AVX512VL_KERNELS (1 or 0; 0 when the
# option is off, and the sources are not built).
#
# Why a separate object library: code compiled with -mavx2 may only run
# where the processor has AVX2. If such a file emitted a copy of a shared
# inline function (an Eigen or standard-library template, say), the linker
# could keep that copy for the whole program, and the baseline path would
# execute AVX2 instructions. The tests <form>_kernels_share_no_code
# therefore check, with nm, that every externally visible symbol these
# objects define belongs to the form (its name carries the form's name),
# and, with objdump, that they hold no fused multiply-add: every form must
# give the bits of the SSE2 form.
#
# Eigen's fixed-size types must also keep the layout the rest of the program
# gives them: with -mavx2 alone, Eigen expects a Quaternion<double> on a
# 32-byte boundary and writes it with aligned AVX stores, while the
# baseline code that owns it aligns it to 16 bytes (a crash seen at
# random addresses, 2026-11-25). EIGEN_MAX_STATIC_ALIGN_BYTES=16 keeps
# Eigen's static alignment at the baseline's in these files.
set(FQ_SIMD_OBJECT_TARGETS_avx2 "" CACHE INTERNAL "")
set(FQ_SIMD_OBJECT_TARGETS_avx512vl "" CACHE INTERNAL "")

function(fq_simd_form_objects_ target form option have_macro flags)
  set(sources ${ARGN})
  if(NOT ${option} OR NOT sources)
    target_compile_definitions(${target} PUBLIC ${have_macro}=0)
    return()
  endif()
  add_library(${target}_${form} OBJECT ${sources})
  target_compile_options(${target}_${form} PRIVATE ${flags})
  # The same include paths, definitions and dependencies as the target.
  target_link_libraries(${target}_${form} PRIVATE $<TARGET_PROPERTY:${target},LINK_LIBRARIES>)
  target_include_directories(${target}_${form} PRIVATE $<TARGET_PROPERTY:${target},INCLUDE_DIRECTORIES>)
  target_compile_definitions(${target}_${form} PRIVATE $<TARGET_PROPERTY:${target},COMPILE_DEFINITIONS>
                                                        ${have_macro}=1 EIGEN_MAX_STATIC_ALIGN_BYTES=16)
  fq_set_warnings(${target}_${form})
  target_sources(${target} PRIVATE $<TARGET_OBJECTS:${target}_${form}>)
  target_compile_definitions(${target} PUBLIC ${have_macro}=1)
  set(FQ_SIMD_OBJECT_TARGETS_${form} ${FQ_SIMD_OBJECT_TARGETS_${form}} ${target}_${form} CACHE INTERNAL "")
endfunction()

function(fq_simd_kernel_sources target)
  cmake_parse_arguments(K "" "" "AVX2;AVX512VL" ${ARGN})
  # FMA stays off in the AVX2 form (-mavx2 does not imply -mfma, and
  # -ffp-contract=off holds).
  fq_simd_form_objects_(${target} avx2 FQ_AVX2_KERNELS FQ_HAVE_AVX2_KERNELS "-mavx2" ${K_AVX2})
  # Eigen refuses -mavx512f without -mfma (its bug 1638), so the flag is
  # given; -ffp-contract=off (set for the whole project, repeated here) keeps
  # GCC from fusing a multiply and an add, the lane kernels call no FMA
  # intrinsic, and the test avx512vl_kernels_share_no_code checks that the
  # objects hold no FMA instruction. -mprefer-vector-width=256 keeps any
  # loop GCC vectorises by itself in 256-bit registers.
  fq_simd_form_objects_(${target} avx512vl FQ_AVX512VL_KERNELS FQ_HAVE_AVX512VL_KERNELS
                        "-mavx2;-mavx512f;-mavx512vl;-mfma;-ffp-contract=off;-mprefer-vector-width=256"
                        ${K_AVX512VL})
endfunction()
