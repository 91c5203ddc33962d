# Install rules: headers, the static (or, with BUILD_SHARED_LIBS, shared) libraries, the CMake
# package (find_package(cellfx) → cellfx::fx, cellfx::terrain, cellfx::cellfx) and cellfx.pc.
# The `cellfx` command is installed when it is built; samples and tests never are.
include(CMakePackageConfigHelpers)

set(CELLFX_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/cellfx")

install(DIRECTORY "${PROJECT_SOURCE_DIR}/fx/include/" "${PROJECT_SOURCE_DIR}/terrain/include/"
        DESTINATION "${CELLFX_INSTALL_INCLUDEDIR}" FILES_MATCHING PATTERN "*.hpp")
install(TARGETS cellfx_fx cellfx_terrain EXPORT cellfxTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
if(TARGET cellfx_cli)
  install(TARGETS cellfx_cli RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
endif()
install(EXPORT cellfxTargets NAMESPACE cellfx:: DESTINATION "${CELLFX_INSTALL_CMAKEDIR}")

configure_package_config_file("${CMAKE_CURRENT_LIST_DIR}/cellfxConfig.cmake.in"
                              "${PROJECT_BINARY_DIR}/cellfxConfig.cmake"
                              INSTALL_DESTINATION "${CELLFX_INSTALL_CMAKEDIR}")
# 0.x: a minor version may change the API.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/cellfxConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/cellfxConfig.cmake" "${PROJECT_BINARY_DIR}/cellfxConfigVersion.cmake"
        DESTINATION "${CELLFX_INSTALL_CMAKEDIR}")

# cellfx.pc: static libraries need their dependencies on the link line, so they are public
# there (Requires/Libs); a shared build moves them to Requires.private/Libs.private.
if(BUILD_SHARED_LIBS)
  set(CELLFX_PC_REQUIRES "glm")
  set(CELLFX_PC_REQUIRES_PRIVATE "epoxy stb")
  set(CELLFX_PC_LIBS_PRIVATE "-pthread")
  set(CELLFX_PC_LIBS_THREADS "")
else()
  set(CELLFX_PC_REQUIRES "glm epoxy stb")
  set(CELLFX_PC_REQUIRES_PRIVATE "")
  set(CELLFX_PC_LIBS_PRIVATE "")
  set(CELLFX_PC_LIBS_THREADS " -pthread")
endif()
# Relocatable: the prefix is found from the .pc file's own folder (cmake --install --prefix).
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(CELLFX_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  file(RELATIVE_PATH CELLFX_PC_UP "/prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/prefix")
  set(CELLFX_PC_PREFIX "\${pcfiledir}/${CELLFX_PC_UP}")
endif()
configure_file("${CMAKE_CURRENT_LIST_DIR}/cellfx.pc.in" "${PROJECT_BINARY_DIR}/cellfx.pc" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/cellfx.pc" DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
