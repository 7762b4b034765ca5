# cmake --install: the program, libvoussoir with its public headers, pkg-config and CMake
# package files, the man page, the documentation and the example cases. Paths follow
# GNUInstallDirs (configured with a /usr prefix on Debian, the library goes to lib/<multiarch>;
# otherwise to lib).
include(CMakePackageConfigHelpers)

set(VS_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/voussoir)

set_target_properties(voussoir PROPERTIES EXPORT_NAME voussoir-cli)
# The program's plugins are the libraries libvoussoir-record and libvoussoir-plot, installed next
# to libvoussoir (the program loads them from the directory its libvoussoir comes from).
install(TARGETS vslib vsrecord vsplot vs_all voussoir EXPORT voussoirTargets
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# The public headers: include/voussoir/ (every header there is API; the private ones stand beside
# their sources in src/) and the generated version.h.
file(GLOB VS_PUBLIC_HEADERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/include/voussoir/*.h)
install(FILES ${VS_PUBLIC_HEADERS} ${PROJECT_BINARY_DIR}/include/voussoir/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/voussoir)

# The MPI plugin (a build with MPI) goes next to them too; it is the program's, not an API.
if(TARGET vsmpi)
  install(TARGETS vsmpi LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
endif()

install(EXPORT voussoirTargets NAMESPACE voussoir:: DESTINATION ${VS_CMAKEDIR})
configure_package_config_file(cmake/voussoirConfig.cmake.in
  ${PROJECT_BINARY_DIR}/voussoirConfig.cmake INSTALL_DESTINATION ${VS_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/voussoirConfigVersion.cmake
  COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/voussoirConfig.cmake
              ${PROJECT_BINARY_DIR}/voussoirConfigVersion.cmake DESTINATION ${VS_CMAKEDIR})

file(RELATIVE_PATH VS_PC_TO_PREFIX "/p/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/p")
configure_file(cmake/voussoir.pc.in ${PROJECT_BINARY_DIR}/voussoir.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/voussoir.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(FILES man/voussoir.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(FILES runs/reference.ini examples/spreading.ini examples/run_case.c
              examples/CMakeLists.txt
        DESTINATION ${CMAKE_INSTALL_DATADIR}/voussoir)
# The Python package, where `voussoir plot` finds it for its charts (PREFIX/bin/voussoir ->
# PREFIX/share/voussoir/python; pip installs it elsewhere too: docs/python.md).
install(DIRECTORY python/voussoir DESTINATION ${CMAKE_INSTALL_DATADIR}/voussoir/python
        PATTERN __pycache__ EXCLUDE)
# The Python gallery and the pvpython script (docs/python.md#gallery): share/voussoir/examples.
install(FILES examples/seed_domain.py examples/pointed_arch.py examples/fragility.py
              examples/load_after_settlement.py examples/paraview_record.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/voussoir/examples)
# The documentation next to the man page, laid out as in the source tree so that its relative
# links hold: share/doc/voussoir/README.md (the front page), docs/ (docs/README.md is its index)
# and the two example files the pages link to.
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)
install(FILES examples/run_case.c examples/CMakeLists.txt
        DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples)
