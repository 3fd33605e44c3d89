# `cmake --install build --prefix PREFIX` puts into PREFIX:
#   bin/brdf                                   the command-line program
#   include/libbrdf/, include/exporters/       the public headers
#   lib/libbrdf.a, lib/libbrdf_exporters.a    the libraries
#   lib/cmake/libbrdf/                         find_package(libbrdf) -> libbrdf::libbrdf, libbrdf::exporters
#   lib/python3.X/site-packages/libbrdf*.so    the Python module (with PREFIX = ~/.local, Debian's
#                                              /usr/bin/python3 finds it without PYTHONPATH: the user site)
#   share/libbrdf/povray/libbrdf.inc           POV-Ray helpers (Brdf_Sun, Brdf_Ortho_Camera)
#   share/libbrdf/blender/libbrdf_materials.zip the Blender add-on, ready for addon_install
#   share/libbrdf/examples/                    the README's quickstart scenes
# tests/install/ checks it by building a consumer project against an installed prefix.
include(CMakePackageConfigHelpers)

set(LIBBRDF_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/libbrdf CACHE STRING
    "Where the CMake package goes, relative to the prefix")
get_target_property(LIBBRDF_LIBRARY_TYPE libbrdf TYPE)

install(TARGETS libbrdf EXPORT libbrdfTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libbrdf/include/libbrdf DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_BINARY_DIR}/libbrdf/include/libbrdf/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/libbrdf)
if(TARGET libbrdf_exporters)
  set_target_properties(libbrdf_exporters PROPERTIES EXPORT_NAME exporters OUTPUT_NAME brdf_exporters)
  target_include_directories(libbrdf_exporters PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  install(TARGETS libbrdf_exporters EXPORT libbrdfTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/exporters/include/exporters DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
install(EXPORT libbrdfTargets NAMESPACE libbrdf:: DESTINATION ${LIBBRDF_CMAKE_INSTALL_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/libbrdfConfig.cmake.in
  ${PROJECT_BINARY_DIR}/libbrdfConfig.cmake INSTALL_DESTINATION ${LIBBRDF_CMAKE_INSTALL_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/libbrdfConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/libbrdfConfig.cmake ${PROJECT_BINARY_DIR}/libbrdfConfigVersion.cmake
        DESTINATION ${LIBBRDF_CMAKE_INSTALL_DIR})

install(TARGETS brdf RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# `brdf bench` plots through this script; the installed brdf finds it beside its prefix's share/.
install(FILES ${PROJECT_SOURCE_DIR}/tools/plot_bench.py DESTINATION ${CMAKE_INSTALL_DATADIR}/libbrdf/tools)

# The Python module: python/CMakeLists.txt (where its interpreter is found).

install(FILES ${PROJECT_SOURCE_DIR}/povray/libbrdf.inc DESTINATION ${CMAKE_INSTALL_DATADIR}/libbrdf/povray)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${CMAKE_INSTALL_DATADIR}/libbrdf/examples)
# The add-on zipped as Blender's installer expects (what blender_addon/package.py writes).
file(GLOB LIBBRDF_ADDON_FILES CONFIGURE_DEPENDS
     ${PROJECT_SOURCE_DIR}/blender_addon/libbrdf_materials/*.py
     ${PROJECT_SOURCE_DIR}/blender_addon/libbrdf_materials/*.toml)
set(LIBBRDF_ADDON_ZIP ${PROJECT_BINARY_DIR}/blender_addon/libbrdf_materials.zip)
add_custom_command(OUTPUT ${LIBBRDF_ADDON_ZIP}
  COMMAND /usr/bin/env python3 ${PROJECT_SOURCE_DIR}/blender_addon/package.py ${PROJECT_BINARY_DIR}/blender_addon
  DEPENDS ${LIBBRDF_ADDON_FILES} ${PROJECT_SOURCE_DIR}/blender_addon/package.py
  COMMENT "Zipping the Blender add-on" VERBATIM)
add_custom_target(libbrdf_blender_addon ALL DEPENDS ${LIBBRDF_ADDON_ZIP})
install(FILES ${LIBBRDF_ADDON_ZIP} DESTINATION ${CMAKE_INSTALL_DATADIR}/libbrdf/blender)
