# cmake/install.cmake: `cmake --install <build> [--prefix P]`, `make install PREFIX=P` and the Debian
# package (`make package`, CPack below); docs/cpp.md, "Install". Included by the top-level
# CMakeLists.txt when ANISO_INSTALL is on (the default for a top-level build).
#
#   P/include/aniso/...              the public headers and their .glsl twins, aniso/version.h
#   P/lib/libaniso_*.a (or .so)      the libraries
#   P/lib/cmake/aniso/               anisoConfig.cmake, its version file, one targets file per component
#   P/lib/pkgconfig/                 aniso.pc, aniso-kernels.pc
#   P/bin/aniso, P/share/aniso/web   the CLI and the browser explorer's page (ANISO_BUILD_APPS)
#   P/lib/python3/dist-packages      the Python package (ANISO_BUILD_PYTHON, python/CMakeLists.txt)
#   P/share/doc/aniso                the docs, the example scenes and the C++ and Python examples
include(CMakePackageConfigHelpers)

set(ANISO_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/aniso)

install(DIRECTORY include/aniso DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev
        FILES_MATCHING PATTERN "*.h" PATTERN "*.glsl")
install(FILES ${PROJECT_BINARY_DIR}/include/aniso/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/aniso COMPONENT dev)

# One export set per find_package component, so that a consumer of the kernels alone needs glm
# only, one of the host library needs no OpenEXR, Embree or Ceres, and one of the fitter no Embree
# (anisoConfig.cmake.in).
#   kernels: aniso::kernels                      header-only, glm
#   host:    aniso::batch, aniso::host, aniso::measured
#   image:   aniso::image                         image files, tone mapping, labels; OpenEXR
#   render:  aniso::render                        Embree 3, tinyobjloader (and image)
#   gl:      aniso::gl                            GLSL export, headless GL host; libepoxy
#   fit:     aniso::fit, aniso::export            Ceres (and image: fitting writes its plots)
#   aniso::aniso, all of them (every component)
set(ANISO_COMPONENT_kernels aniso_kernels)
set(ANISO_COMPONENT_host aniso_batch aniso_host aniso_measured)
set(ANISO_COMPONENT_image aniso_image)
set(ANISO_COMPONENT_render aniso_render)
set(ANISO_COMPONENT_gl aniso_gl)
set(ANISO_COMPONENT_fit aniso_fit aniso_export)
set(ANISO_COMPONENT_all aniso_all)
foreach(component kernels host image render gl fit all)
  install(TARGETS ${ANISO_COMPONENT_${component}} EXPORT aniso_${component}
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev)
  install(EXPORT aniso_${component} NAMESPACE aniso:: FILE aniso-${component}-targets.cmake
          DESTINATION ${ANISO_CMAKE_DIR} COMPONENT dev)
endforeach()

configure_package_config_file(cmake/anisoConfig.cmake.in ${PROJECT_BINARY_DIR}/anisoConfig.cmake
                              INSTALL_DESTINATION ${ANISO_CMAKE_DIR})
# 0.x: a minor version may change the API, so only the same major.minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/anisoConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/anisoConfig.cmake ${PROJECT_BINARY_DIR}/anisoConfigVersion.cmake
        DESTINATION ${ANISO_CMAKE_DIR} COMPONENT dev)

# pkg-config: aniso-kernels.pc (glm and the include path) and aniso.pc (every library). The
# libraries are static by default, so aniso.pc lists what they link in Libs and Requires; Ceres and
# Embree have no .pc file in Debian and are named with -l.
if(BUILD_SHARED_LIBS)
  set(ANISO_PC_REQUIRES "aniso-kernels fmt nlohmann_json")
  set(ANISO_PC_REQUIRES_PRIVATE "tbb libhwy libhwy-contrib libcrypto OpenEXR tinyobjloader epoxy libglog")
  set(ANISO_PC_LIBS_PRIVATE "-lceres -lembree3")
  set(ANISO_PC_LIBS_PRIVATE_STATIC "")
else()
  # libglog: the fit library calls google::InitGoogleLogging (Ceres' logging) itself.
  set(ANISO_PC_REQUIRES "aniso-kernels fmt nlohmann_json tbb libhwy libhwy-contrib libcrypto OpenEXR tinyobjloader epoxy libglog")
  set(ANISO_PC_REQUIRES_PRIVATE "")
  set(ANISO_PC_LIBS_PRIVATE "")
  set(ANISO_PC_LIBS_PRIVATE_STATIC "-lceres -lembree3")
endif()
# Relocatable: the prefix is found from the .pc file's own folder (pkg-config's ${pcfiledir}), so
# `cmake --install --prefix P` and the .deb (/usr) give correct paths.
file(RELATIVE_PATH ANISO_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
foreach(pc aniso aniso-kernels)
  configure_file(cmake/${pc}.pc.in ${PROJECT_BINARY_DIR}/pkgconfig/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/pkgconfig/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)
endforeach()

if(ANISO_BUILD_APPS)
  install(TARGETS aniso RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  # `aniso serve` finds the page at <prefix>/share/aniso/web (apps/aniso/cmd_web.cpp).
  install(DIRECTORY ${PROJECT_BINARY_DIR}/web/ DESTINATION ${CMAKE_INSTALL_DATADIR}/aniso/web COMPONENT runtime)
endif()
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT doc)
install(DIRECTORY examples/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples COMPONENT doc
        PATTERN "build*" EXCLUDE)
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT doc)

# A shared build's executable finds the libraries under the prefix (their SONAME, version script
# and RPATH: the top-level CMakeLists.txt).
if(BUILD_SHARED_LIBS AND ANISO_BUILD_APPS)
  set_target_properties(aniso PROPERTIES INSTALL_RPATH "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
endif()

# The Debian package: `make package` -> build/<preset>/aniso_<version>_amd64.deb, everything above
# under /usr. Depends: the shared libraries the binaries load (dpkg-shlibdeps) and the -dev packages
# the installed headers, CMake config and static libraries need from a consumer.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME aniso)
set(CPACK_PACKAGE_VENDOR "aniso")
set(CPACK_PACKAGE_CONTACT "aniso developers <aniso@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "anisotropic and measured reflectance: kernels, renderer, fitting, exports")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libglm-dev, libfmt-dev, nlohmann-json3-dev, libtbb-dev, libhwy-dev, libssl-dev, libembree-dev, libopenexr-dev, libtinyobjloader-dev, libepoxy-dev, libceres-dev, pkg-config, python3-numpy")
set(CPACK_COMPONENTS_ALL runtime dev python doc)
set(CPACK_DEB_COMPONENT_INSTALL OFF)
include(CPack)
