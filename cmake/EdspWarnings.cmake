# edsp_set_warnings(<target>): the warning set every edsp target compiles with.
# Strict enough to catch the usual numeric bugs (shadowing, narrowing, silent
# double->int conversions); -Werror only when EDSP_WERROR is on (CI). A switch
# over an enum that misses a value is always an error: the effect vocabulary
# and the bridge's states are such enums, and a forgotten case compiles to a
# silent no-op (docs/extending.md).
function(edsp_set_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
    -Wnon-virtual-dtor -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion -Werror=switch)
  if(EDSP_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
