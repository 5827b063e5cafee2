# How every edsp library and program is declared, so that each has the same
# alias, include folder, warnings and install rules.
#
# edsp_add_library(<name> SOURCES <file>... [LINK <target_link_libraries args>...])
#   edsp_<name>, aliased edsp::<name>, with <dir>/include public, where <dir>
#   is the folder of the CMakeLists.txt that declares it. A library named in
#   EDSP_EXPORTED_LIBRARIES is installed with its headers and exported as
#   edsp::<name> (find_package(edsp)); what it links must be exported too, or
#   CMake refuses to generate.
# edsp_add_program(<name> SOURCES <file>... [LINK <target_link_libraries args>...])
#   the executable <name> (an edsp-… command), installed to bin unless the
#   declaring folder sets EDSP_INSTALL_PROGRAMS OFF (the benchmarks). Its own
#   sources compile at -O1 unless the folder sets EDSP_PROGRAMS_OPTIMIZED ON.
include_guard(GLOBAL)
include(GNUInstallDirs)

# What a program outside the tree builds on: the kinematics and its
# calibration, the message types and the bus, a node's plumbing, the planner
# and its motion client, the log reader. The rest serves edsp's own programs.
set(EDSP_EXPORTED_LIBRARIES config_file transport node kinematics calibration kinematics_node planner planner_node motion_design
    logger)

# Installs <dir>/include once for all the libraries a folder declares.
function(edsp_install_headers dir)
  get_property(done GLOBAL PROPERTY EDSP_INSTALLED_HEADER_DIRS)
  if(NOT dir IN_LIST done)
    set_property(GLOBAL APPEND PROPERTY EDSP_INSTALLED_HEADER_DIRS ${dir})
    install(DIRECTORY ${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()

function(edsp_add_library name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "" "SOURCES;LINK")
  add_library(edsp_${name} ${ARG_SOURCES})
  add_library(edsp::${name} ALIAS edsp_${name})
  target_include_directories(edsp_${name} PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
                                                 $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  if(ARG_LINK)
    target_link_libraries(edsp_${name} ${ARG_LINK})
  endif()
  edsp_set_warnings(edsp_${name})
  add_dependencies(edsp_${name} edsp_layer_check)  # a build of any one target checks the layers too
  if(name IN_LIST EDSP_EXPORTED_LIBRARIES)
    set_target_properties(edsp_${name} PROPERTIES EXPORT_NAME ${name})
    install(TARGETS edsp_${name} EXPORT edspTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
    edsp_install_headers(${CMAKE_CURRENT_SOURCE_DIR}/include)
  endif()
endfunction()

function(edsp_add_program name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "" "SOURCES;LINK")
  add_executable(${name} ${ARG_SOURCES})
  if(ARG_LINK)
    target_link_libraries(${name} ${ARG_LINK})
  endif()
  edsp_set_warnings(${name})
  # A program's own sources parse its options and wire libraries together;
  # its work runs in the libraries, at the build type's optimisation. At -O1
  # they compile much faster (most of their time is CLI11's header, which
  # every program includes; docs/figures.md). The benchmarks, whose own code is
  # what they measure, keep the build type's level.
  if(NOT EDSP_PROGRAMS_OPTIMIZED)
    target_compile_options(${name} PRIVATE $<$<NOT:$<CONFIG:Debug>>:-O1>)
  endif()
  add_dependencies(${name} edsp_layer_check)
  if(NOT DEFINED EDSP_INSTALL_PROGRAMS OR EDSP_INSTALL_PROGRAMS)
    install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endfunction()
