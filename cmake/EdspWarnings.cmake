# edsp_set_warnings(<target>): the warning set every edsp target compiles with.
# Strict enough to catch the usual numeric bugs (shadowing, narrowing, silent
# double->int conversions); -Werror only when EDSP_WERROR is on (CI).
function(edsp_set_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
    -Wnon-virtual-dtor -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion)
  if(EDSP_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
