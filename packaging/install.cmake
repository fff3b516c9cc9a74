# Installation layout, the CMake package config for downstream projects, and the Debian
# packages. Two components, packaged apart by CPack:
# runtime (package wavecam):
#   bin/wavecam                               the command line
#   share/man/man1/wavecam.1.gz               its man page (help2man, from --help)
#   lib[/<arch>]/wavecam/wavecam.imageio.so   the OIIO plugin
#   /etc/profile.d/wavecam.sh                 (package only) puts that folder on OIIO_LIBRARY_PATH
#   share/wavecam/ocio/wavecam.ocio           the OCIO config (found by the libraries by default)
#   share/wavecam/blender/wavecam_blender.zip the Blender add-on (Preferences > Add-ons > Install)
#   share/doc/wavecam/copyright               the licences (Apache-2.0; CLI11, toml++ compiled in)
# dev (package wavecam-dev):
#   lib[/<arch>]/libwavecam.a, libwavecam_io.a  the libraries (position-independent, static)
#   include/wavecam/*.h                       their headers
#   lib[/<arch>]/cmake/wavecam/               find_package(wavecam) -> wavecam::core, wavecam::io
# The test-scene tracer (component tracer) is installed by `cmake --install`, not packaged.
include(CMakePackageConfigHelpers)

set(WAVECAM_PLUGIN_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/wavecam")
set(WAVECAM_CMAKE_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/wavecam")
set(WAVECAM_OCIO_INSTALL_DIR "${CMAKE_INSTALL_DATADIR}/wavecam/ocio")

set_target_properties(wavecam_core PROPERTIES EXPORT_NAME core)
set_target_properties(wavecam_io PROPERTIES EXPORT_NAME io)
install(TARGETS wavecam_core wavecam_io EXPORT wavecamTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY core/include/wavecam core/io/include/wavecam DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
install(TARGETS wavecam RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
if(WAVECAM_MAN_PAGE)
  install(FILES ${WAVECAM_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
endif()
install(TARGETS wavecam_imageio LIBRARY DESTINATION ${WAVECAM_PLUGIN_INSTALL_DIR} COMPONENT runtime)
install(FILES ocio_configs/wavecam.ocio DESTINATION ${WAVECAM_OCIO_INSTALL_DIR} COMPONENT runtime)
# Debian's place for the licence: /usr/share/doc/wavecam/copyright (machine-readable format).
install(FILES packaging/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
install(FILES ${WAVECAM_BLENDER_ZIP} DESTINATION ${CMAKE_INSTALL_DATADIR}/wavecam/blender COMPONENT runtime)

if(WAVECAM_VULKAN_BUILT)
  set(WAVECAM_VULKAN_BUILT_OR_OFF ON)
else()
  set(WAVECAM_VULKAN_BUILT_OR_OFF OFF)
endif()
# OpenImageIO 2.4 looks for plugins only on OIIO_LIBRARY_PATH (and LD_LIBRARY_PATH): it has no
# folder of its own to search. The package sets the variable for login shells; EXCLUDE_FROM_ALL
# keeps /etc out of a plain `cmake --install --prefix DIR`.
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(WAVECAM_PACKAGED_PLUGIN_DIR "${CPACK_PACKAGING_INSTALL_PREFIX}/${WAVECAM_PLUGIN_INSTALL_DIR}")
configure_file(packaging/profile.sh.in ${CMAKE_CURRENT_BINARY_DIR}/wavecam.sh @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/wavecam.sh DESTINATION /etc/profile.d COMPONENT runtime EXCLUDE_FROM_ALL)

install(EXPORT wavecamTargets NAMESPACE wavecam:: DESTINATION ${WAVECAM_CMAKE_INSTALL_DIR} COMPONENT dev)
configure_package_config_file(packaging/wavecamConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/wavecamConfig.cmake
  INSTALL_DESTINATION ${WAVECAM_CMAKE_INSTALL_DIR}
  PATH_VARS WAVECAM_PLUGIN_INSTALL_DIR WAVECAM_OCIO_INSTALL_DIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/wavecamConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/wavecamConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/wavecamConfigVersion.cmake
  DESTINATION ${WAVECAM_CMAKE_INSTALL_DIR} COMPONENT dev)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME wavecam)
set(CPACK_PACKAGE_VENDOR "wavecam")
set(CPACK_PACKAGE_CONTACT "wavecam developers <dev@wavecam.invalid>")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_COMPONENTS_ALL runtime dev)  # not the tracer
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME wavecam)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION graphics)
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION "Wave-optics pinhole camera: diffraction for rendered images
The wavecam command diffracts a render (RGB radiance and depth, OpenEXR) through a real
pinhole; an OpenImageIO plugin does the same when oiiotool or a program reads NAME.wavecam;
a Blender add-on diffracts every rendered frame.")
# the shared libraries the command and the plugin link (OpenImageIO, OpenColorIO, ...)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
# oiiotool and the Python bindings read images through the plugin; the add-on runs in Blender
# and tags frames through OpenImageIO's Python
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "openimageio-tools, python3-openimageio, blender")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME wavecam-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_COMPONENT_DEV_DESCRIPTION "Wave-optics pinhole camera: static libraries and headers
libwavecam (the physics) and libwavecam_io (its OpenImageIO layer), their headers and the
CMake package: find_package(wavecam) gives wavecam::core and wavecam::io.")
# static libraries: what they link is what a program built with them needs
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
  "wavecam (= ${PROJECT_VERSION}), libopenimageio-dev, libopencolorio-dev, pkg-config")
if(WAVECAM_VULKAN_BUILT)  # the static library's users link the Vulkan loader too
  string(APPEND CPACK_DEBIAN_DEV_PACKAGE_DEPENDS ", libvulkan-dev")
endif()
include(CPack)
