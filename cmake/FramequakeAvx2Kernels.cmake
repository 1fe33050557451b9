# AVX2 forms of the SIMD lane kernels (option FQ_AVX2_KERNELS; dem_core/lanes.h,
# dem_core/lane_isa.h).
#
# fq_avx2_kernel_sources(<target> <source>...) compiles the sources with
# -mavx2 into an object library <target>_avx2 linked into <target>, and
# tells every user of <target> FQ_HAVE_AVX2_KERNELS=1 (0 when the option is
# off, and the sources are not built).
#
# Why a separate object library: code compiled with -mavx2 may only run
# where the processor has AVX2. If such a file emitted a copy of a shared
# inline function (an Eigen or standard-library template, say), the linker
# could keep that copy for the whole program, and the baseline path would
# execute AVX2 instructions. The test avx2_kernels_share_no_code therefore
# checks, with nm, that every externally visible symbol these objects
# define belongs to the avx2 forms (their names carry "avx2").
#
# Eigen's fixed-size types must also keep the layout the rest of the program
# gives them: with -mavx2 alone, Eigen expects a Quaternion<double> on a
# 32-byte boundary and writes it with aligned AVX stores, while the
# baseline code that owns it aligns it to 16 bytes (a crash seen at
# random addresses, 2026-11-25). EIGEN_MAX_STATIC_ALIGN_BYTES=16 keeps
# Eigen's static alignment at the baseline's in these files.
set(FQ_AVX2_OBJECT_TARGETS "" CACHE INTERNAL "")

function(fq_avx2_kernel_sources target)
  if(NOT FQ_AVX2_KERNELS)
    target_compile_definitions(${target} PUBLIC FQ_HAVE_AVX2_KERNELS=0)
    return()
  endif()
  add_library(${target}_avx2 OBJECT ${ARGN})
  # FMA stays off (-mavx2 does not imply -mfma, and -ffp-contract=off holds):
  # the AVX2 form must give the bits of the SSE2 form.
  target_compile_options(${target}_avx2 PRIVATE -mavx2)
  # The same include paths, definitions and dependencies as the target.
  target_link_libraries(${target}_avx2 PRIVATE $<TARGET_PROPERTY:${target},LINK_LIBRARIES>)
  target_include_directories(${target}_avx2 PRIVATE $<TARGET_PROPERTY:${target},INCLUDE_DIRECTORIES>)
  target_compile_definitions(${target}_avx2 PRIVATE $<TARGET_PROPERTY:${target},COMPILE_DEFINITIONS>
                                                      FQ_HAVE_AVX2_KERNELS=1 EIGEN_MAX_STATIC_ALIGN_BYTES=16)
  fq_set_warnings(${target}_avx2)
  target_sources(${target} PRIVATE $<TARGET_OBJECTS:${target}_avx2>)
  target_compile_definitions(${target} PUBLIC FQ_HAVE_AVX2_KERNELS=1)
  set(FQ_AVX2_OBJECT_TARGETS ${FQ_AVX2_OBJECT_TARGETS} ${target}_avx2 CACHE INTERNAL "")
endfunction()
