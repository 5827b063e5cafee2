# What `cmake --install` puts where, beside the programs, libraries and
# headers that edsp_add_program and edsp_add_library install
# (docs/install.md), and the Debian package CPack makes of it:
#   share/edsp/{groups,config}    group files, and the configs they name relative to share/edsp
#   lib/systemd/system            the units, their paths rewritten for this prefix
#   share/doc/edsp                the docs the units point at
#   lib/cmake/edsp                edspConfig.cmake: find_package(edsp), targets edsp::…
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(EDSP_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/edsp)
set(EDSP_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/edsp)
# Not LIBDIR: systemd looks in lib/systemd/system under /usr and /usr/local,
# never in Debian's multiarch folder.
set(EDSP_INSTALL_SYSTEMDUNITDIR lib/systemd/system CACHE STRING
    "where cmake --install puts the systemd units, relative to the prefix")

install(DIRECTORY ${PROJECT_SOURCE_DIR}/deploy/groups/ DESTINATION ${EDSP_INSTALL_DATADIR}/groups)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/config/ DESTINATION ${EDSP_INSTALL_DATADIR}/config)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} PATTERN notes EXCLUDE)

# The units in deploy/systemd assume a checkout at /opt/edsp; the installed
# ones are written at install time, when the prefix is known.
set(edsp_units edsp-group@.service edsp@.service)
list(TRANSFORM edsp_units PREPEND ${PROJECT_SOURCE_DIR}/deploy/systemd/)
install(CODE "
  set(EDSP_UNITS \"${edsp_units}\")
  set(EDSP_UNIT_STAGING \"${PROJECT_BINARY_DIR}/installed-units\")
  set(EDSP_UNIT_DIR \"${EDSP_INSTALL_SYSTEMDUNITDIR}\")
  set(EDSP_BIN_DIR \"${CMAKE_INSTALL_BINDIR}\")
  set(EDSP_DATA_DIR \"${EDSP_INSTALL_DATADIR}\")
  set(EDSP_DOC_DIR \"${CMAKE_INSTALL_DOCDIR}\")
  include(\"${PROJECT_SOURCE_DIR}/cmake/EdspInstallUnits.cmake\")")

install(EXPORT edspTargets NAMESPACE edsp:: FILE edspTargets.cmake DESTINATION ${EDSP_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/edspConfig.cmake.in
  ${PROJECT_BINARY_DIR}/edspConfig.cmake INSTALL_DESTINATION ${EDSP_INSTALL_CMAKEDIR}
  PATH_VARS EDSP_INSTALL_DATADIR)
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/edspConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/edspConfig.cmake ${PROJECT_BINARY_DIR}/edspConfigVersion.cmake
  DESTINATION ${EDSP_INSTALL_CMAKEDIR})

# cpack -G DEB in the build tree: one package, edsp, installed under /usr.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME edsp)
set(CPACK_PACKAGE_VENDOR edsp)
set(CPACK_PACKAGE_CONTACT "edsp maintainers <edsp-maintainers@example.org>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "control stack for electrically driven Stewart platforms (signed passive-rotation compensation)")
set(CPACK_PACKAGE_DESCRIPTION
    "edsp commands a six-leg electrically driven Stewart platform, compensates its lead screws' passive rotation, \
records every channel and diagnoses the gap between the measured platform and the model. The package holds the \
programs, the group files, configs and systemd units, the Python package, the lcm-spy jar, and the static \
libraries, headers and CMake package for find_package(edsp).")
# Staged through DESTDIR with the prefix /usr, so that what is written at
# install time (the units) names /usr rather than cpack's staging folder.
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_SET_DESTDIR ON)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# Depends from the programs' shared libraries (dpkg-shlibdeps reads the
# local dpkg database, no network); without dpkg-dev and file, a hand list
# of what they link on Debian 12 (Ceres statically, its solvers not).
find_program(EDSP_DPKG_SHLIBDEPS dpkg-shlibdeps)
find_program(EDSP_FILE file)
if(EDSP_DPKG_SHLIBDEPS AND EDSP_FILE)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
else()
  set(CPACK_DEBIAN_PACKAGE_DEPENDS
      "libc6, libstdc++6, libgcc-s1, liblcm1, libglib2.0-0, libmodbus5, libfmt9, libtomlplusplus3, \
libgoogle-glog0v6, libcholmod3, libspqr2, libcxsparse3, liblapack3, libatlas3-base")
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-numpy, libjs-three, libjs-dygraphs")  # the panel's 3-D view and plots
# What find_package(edsp) finds its dependencies with, and lcm-spy's jar.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libeigen3-dev, libtomlplusplus-dev, libfmt-dev, libcli11-dev, nlohmann-json3-dev, \
libboost-dev, liblcm-dev, pkg-config, liblcm-java")
include(CPack)
