# cmake --install: the public headers, libfemto.a and libfemto.so (versioned soname), the femto
# tool (cli/CMakeLists.txt), lib/cmake/femto/femtoConfig.cmake with its version file and the
# exported targets femto::femto_static and femto::femto_shared (femto::femto, an alias chosen in
# femtoConfig.cmake), and lib/pkgconfig/femto.pc. Included by the top-level CMakeLists.txt when
# FEMTO_INSTALL is on.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/femto DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(TARGETS femto_static femto_shared EXPORT femtoTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Development
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

set(FEMTO_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/femto)
install(EXPORT femtoTargets NAMESPACE femto:: DESTINATION ${FEMTO_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/femtoConfig.cmake.in
  ${PROJECT_BINARY_DIR}/femtoConfig.cmake INSTALL_DESTINATION ${FEMTO_CMAKE_DIR})
# 0.x releases change the API between minor versions: only the same minor version is compatible.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(FEMTO_COMPATIBILITY SameMinorVersion)
else()
  set(FEMTO_COMPATIBILITY SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/femtoConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY ${FEMTO_COMPATIBILITY})
install(FILES ${PROJECT_BINARY_DIR}/femtoConfig.cmake ${PROJECT_BINARY_DIR}/femtoConfigVersion.cmake
        DESTINATION ${FEMTO_CMAKE_DIR})

# pkg-config: relocatable (the prefix is computed from the .pc file's place).
file(RELATIVE_PATH FEMTO_PC_TO_PREFIX /root/${CMAKE_INSTALL_LIBDIR}/pkgconfig /root)
string(REGEX REPLACE "/$" "" FEMTO_PC_TO_PREFIX "${FEMTO_PC_TO_PREFIX}")
set(FEMTO_PC_REQUIRES_PRIVATE "")
if(FEMTO_ZLIB_FOUND)
  set(FEMTO_PC_REQUIRES_PRIVATE "zlib")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/femto.pc.in ${PROJECT_BINARY_DIR}/femto.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/femto.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
