# `cmake --install build --prefix PREFIX` installs the library the way a user links it:
# every module's static library, the public headers (vdblight/<module>/*.h, all included by vdblight/vdblight.h)
# and a CMake package, so that `find_package(vdblight)` gives `vdblight::vdblight`
# (examples/CMakeLists.txt; tests/install_example_test.sh builds the example against it).
include(CMakePackageConfigHelpers)

get_property(_vdblight_modules GLOBAL PROPERTY VDBLIGHT_MODULES)
install(TARGETS vdblight vdblight_flags ${_vdblight_modules}
        EXPORT vdblightTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libvdblight/include/vdblight
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT vdblightTargets NAMESPACE vdblight:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vdblight)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/vdblightConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/vdblightConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vdblight)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/vdblightConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/vdblightConfig.cmake ${PROJECT_BINARY_DIR}/vdblightConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vdblight)
# The PNanoVDB lookup of `export --format nanovdb` files, for shaders (C, GLSL, HLSL; docs/engines.md).
install(FILES ${PROJECT_SOURCE_DIR}/shaders/vdblight_nanovdb.h ${PROJECT_SOURCE_DIR}/shaders/vdblight_nanovdb_lights.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vdblight/shaders)
