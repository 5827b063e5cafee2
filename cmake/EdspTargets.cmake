# How every edsp library and program is declared, so that each has the same
# alias, include folder and warnings.
#
# edsp_add_library(<name> SOURCES <file>... [LINK <target_link_libraries args>...])
#   edsp_<name>, aliased edsp::<name>, with <dir>/include public, where <dir>
#   is the folder of the CMakeLists.txt that declares it.
# edsp_add_program(<name> SOURCES <file>... [LINK <target_link_libraries args>...])
#   the executable <name> (an edsp-… command).
include_guard(GLOBAL)

function(edsp_add_library name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "" "SOURCES;LINK")
  add_library(edsp_${name} ${ARG_SOURCES})
  add_library(edsp::${name} ALIAS edsp_${name})
  target_include_directories(edsp_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  if(ARG_LINK)
    target_link_libraries(edsp_${name} ${ARG_LINK})
  endif()
  edsp_set_warnings(edsp_${name})
endfunction()

function(edsp_add_program name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "" "SOURCES;LINK")
  add_executable(${name} ${ARG_SOURCES})
  if(ARG_LINK)
    target_link_libraries(${name} ${ARG_LINK})
  endif()
  edsp_set_warnings(${name})
endfunction()
