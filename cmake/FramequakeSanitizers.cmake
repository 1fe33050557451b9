# FQ_SANITIZE=address | undefined | address,undefined: instrument every target.
if(FQ_SANITIZE)
  set(_allowed "address" "undefined" "address,undefined" "undefined,address")
  if(NOT FQ_SANITIZE IN_LIST _allowed)
    message(FATAL_ERROR "FQ_SANITIZE='${FQ_SANITIZE}' is not one of: ${_allowed}")
  endif()
  add_compile_options(-fsanitize=${FQ_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${FQ_SANITIZE})
endif()
