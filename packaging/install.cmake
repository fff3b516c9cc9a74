# Installation layout, the CMake package config for downstream projects, and the .deb.
#   bin/wavecam                               the command line
#   lib[/<arch>]/libwavecam.a, libwavecam_io.a  the libraries (position-independent, static)
#   include/wavecam/*.h                       their headers
#   lib[/<arch>]/wavecam/wavecam.imageio.so     the OIIO plugin: put this folder on OIIO_LIBRARY_PATH
#   share/wavecam/ocio/wavecam.ocio           the OCIO config (found by the libraries by default)
#   share/wavecam/blender/wavecam_blender.zip the Blender add-on (Preferences > Add-ons > Install)
#   lib[/<arch>]/cmake/wavecam/                 find_package(wavecam) -> wavecam::core, wavecam::io
#   share/doc/wavecam/copyright               the licences (Apache-2.0; CLI11, toml++ compiled in)
include(CMakePackageConfigHelpers)

set(WAVECAM_PLUGIN_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/wavecam")
set(WAVECAM_CMAKE_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/wavecam")
set(WAVECAM_OCIO_INSTALL_DIR "${CMAKE_INSTALL_DATADIR}/wavecam/ocio")

set_target_properties(wavecam_core PROPERTIES EXPORT_NAME core)
set_target_properties(wavecam_io PROPERTIES EXPORT_NAME io)
install(TARGETS wavecam_core wavecam_io EXPORT wavecamTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY core/include/wavecam core/io/include/wavecam DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS wavecam RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS wavecam_imageio LIBRARY DESTINATION ${WAVECAM_PLUGIN_INSTALL_DIR})
install(FILES ocio_configs/wavecam.ocio DESTINATION ${WAVECAM_OCIO_INSTALL_DIR})
# Debian's place for the licence: /usr/share/doc/wavecam/copyright (machine-readable format).
install(FILES packaging/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${WAVECAM_BLENDER_ZIP} DESTINATION ${CMAKE_INSTALL_DATADIR}/wavecam/blender)

install(EXPORT wavecamTargets NAMESPACE wavecam:: DESTINATION ${WAVECAM_CMAKE_INSTALL_DIR})
configure_package_config_file(packaging/wavecamConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/wavecamConfig.cmake
  INSTALL_DESTINATION ${WAVECAM_CMAKE_INSTALL_DIR}
  PATH_VARS WAVECAM_PLUGIN_INSTALL_DIR WAVECAM_OCIO_INSTALL_DIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/wavecamConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/wavecamConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/wavecamConfigVersion.cmake
  DESTINATION ${WAVECAM_CMAKE_INSTALL_DIR})

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME wavecam)
set(CPACK_PACKAGE_VENDOR "wavecam")
set(CPACK_PACKAGE_CONTACT "wavecam developers <dev@wavecam.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Wave-optics pinhole camera: diffraction for rendered images (CLI, OIIO plugin, library)")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libopenimageio-dev, libopencolorio-dev, libkissfft-dev")
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
# the Blender add-on runs in Debian's Blender and tags frames through OIIO's Python bindings
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "blender, python3-openimageio")
include(CPack)
