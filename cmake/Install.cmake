# cmake --install: headers, static libraries, the CMake package (find_package(certray) gives
# certray::certray) and a pkg-config file. Headers keep their folders under include/certray/, so
# `#include <certray/certray.h>` works and the library's own includes ("expr/tape.h") resolve.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(certray_libs certray_flags certray_interval certray_expr certray_solvers certray_tracers certray_png
    certray_api certray)
install(TARGETS ${certray_libs} EXPORT certrayTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT certrayTargets NAMESPACE certray:: FILE certrayTargets.cmake
    DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/certray)
foreach(dir interval expr solvers tracers)
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/certray/${dir}
        FILES_MATCHING PATTERN "*.h")
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/certray/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/certray
    FILES_MATCHING PATTERN "*.h")

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/certrayConfig.cmake.in
    ${PROJECT_BINARY_DIR}/certrayConfig.cmake
    INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/certray)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/certrayConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/certrayConfig.cmake ${PROJECT_BINARY_DIR}/certrayConfigVersion.cmake
    DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/certray)

configure_file(${PROJECT_SOURCE_DIR}/cmake/certray.pc.in ${PROJECT_BINARY_DIR}/certray.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/certray.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
