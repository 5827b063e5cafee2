# -DEDSP_SANITIZE=address,undefined (or thread): every target of the tree,
# with frame pointers for readable reports. UBSan does not recover, so any
# report fails the test that triggered it. Use a build directory of its own:
#   cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEDSP_SANITIZE=address,undefined
if(EDSP_SANITIZE)
  if(EDSP_SANITIZE MATCHES "thread" AND EDSP_SANITIZE MATCHES "address")
    message(FATAL_ERROR "EDSP_SANITIZE=${EDSP_SANITIZE}: thread and address cannot be combined")
  endif()
  set(edsp_sanitize_flags -fsanitize=${EDSP_SANITIZE} -fno-omit-frame-pointer)
  if(EDSP_SANITIZE MATCHES "undefined")
    list(APPEND edsp_sanitize_flags -fno-sanitize-recover=undefined)
  endif()
  add_compile_options(${edsp_sanitize_flags})
  add_link_options(${edsp_sanitize_flags})
  message(STATUS "edsp: sanitizers ${EDSP_SANITIZE}")
endif()
