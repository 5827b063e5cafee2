# Run by `cmake --install` (cmake/EdspInstall.cmake): writes the systemd
# units of deploy/systemd with this installation's paths in place of the
# checkout's (/opt/edsp, its build/bin and deploy/groups), and installs them.
# A unit line that still points into a checkout stops the install, naming
# it: a new path in a unit needs its installed counterpart here.
#
# In: EDSP_UNITS (source files), EDSP_UNIT_STAGING (a build-tree folder),
# EDSP_UNIT_DIR, EDSP_BIN_DIR, EDSP_DATA_DIR, EDSP_DOC_DIR (relative to
# the prefix, or absolute), and cmake --install's CMAKE_INSTALL_PREFIX.
foreach(var EDSP_BIN_DIR EDSP_DATA_DIR EDSP_DOC_DIR EDSP_UNIT_DIR)
  cmake_path(ABSOLUTE_PATH ${var} BASE_DIRECTORY "${CMAKE_INSTALL_PREFIX}" NORMALIZE OUTPUT_VARIABLE ${var}_FULL)
endforeach()

foreach(source IN LISTS EDSP_UNITS)
  cmake_path(GET source FILENAME name)
  file(READ "${source}" text)
  # The checkout's instructions (cp, deploy/edsp) give way to these.
  string(REGEX REPLACE "^(#[^\n]*\n)+" "" text "${text}")
  # Most specific first: /opt/edsp alone is EDSP_ROOT.
  string(REPLACE "\${EDSP_ROOT}/build/bin" "${EDSP_BIN_DIR_FULL}" text "${text}")
  string(REPLACE "\${EDSP_ROOT}/deploy/groups" "\${EDSP_ROOT}/groups" text "${text}")
  string(REPLACE "/opt/edsp/build/bin" "${EDSP_BIN_DIR_FULL}" text "${text}")
  string(REPLACE "file:/opt/edsp/docs" "file:${EDSP_DOC_DIR_FULL}" text "${text}")
  string(REPLACE "/opt/edsp" "${EDSP_DATA_DIR_FULL}" text "${text}")
  string(REGEX MATCH "(^|\n)[^#\n][^\n]*(/opt/edsp|build/bin|deploy/)[^\n]*" stale "${text}")
  if(stale)
    string(STRIP "${stale}" stale)
    message(FATAL_ERROR "deploy/systemd/${name}: \"${stale}\" points into a checkout; "
                        "cmake/EdspInstallUnits.cmake knows no installed path for it")
  endif()
  file(WRITE "${EDSP_UNIT_STAGING}/${name}"
       "# Installed from edsp's deploy/systemd/${name} with this installation's paths:\n"
       "# programs in ${EDSP_BIN_DIR_FULL}, EDSP_ROOT ${EDSP_DATA_DIR_FULL} (groups/, config/).\n"
       "# How to enable them: ${EDSP_DOC_DIR_FULL}/install.md.\n" "${text}")
  file(INSTALL DESTINATION "${EDSP_UNIT_DIR_FULL}" TYPE FILE FILES "${EDSP_UNIT_STAGING}/${name}")
endforeach()
