# FQ_SANITIZE=address | undefined | address,undefined: instrument every target.
if(FQ_SANITIZE)
  set(_allowed "address" "undefined" "address,undefined" "undefined,address")
  if(NOT FQ_SANITIZE IN_LIST _allowed)
    message(FATAL_ERROR "FQ_SANITIZE='${FQ_SANITIZE}' is not one of: ${_allowed}")
  endif()
  # -O1 (after the build type's -O2, so it wins): the level the sanitizers'
  # documentation suggests, and it halves the compile time of a test file
  # under instrumentation (14.8 -> 8.0 s for test_fracture_and_damping.cpp),
  # which is most of CI's budget.
  add_compile_options(-fsanitize=${FQ_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all -O1)
  add_link_options(-fsanitize=${FQ_SANITIZE})
endif()
