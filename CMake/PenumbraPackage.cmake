# SPDX-License-Identifier: GPL-3.0-or-later
# The installable CMake package: find_package(Penumbra) gives the targets
# Penumbra::Filters (the VTK filters) and the core modules (Penumbra::Common,
# ::Visibility, ::Reconstruction, ::Meshing, ::Transport, ::Baseline).
include(CMakePackageConfigHelpers)

install(EXPORT Penumbra
  NAMESPACE   Penumbra::
  FILE        PenumbraTargets.cmake
  DESTINATION "${PENUMBRA_CMAKE_DESTINATION}"
  COMPONENT   development)
export(EXPORT Penumbra
  NAMESPACE   Penumbra::
  FILE        "${CMAKE_BINARY_DIR}/${PENUMBRA_CMAKE_DESTINATION}/PenumbraTargets.cmake")

configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/PenumbraConfig.cmake.in"
  "${CMAKE_BINARY_DIR}/${PENUMBRA_CMAKE_DESTINATION}/PenumbraConfig.cmake"
  INSTALL_DESTINATION "${PENUMBRA_CMAKE_DESTINATION}")
write_basic_package_version_file(
  "${CMAKE_BINARY_DIR}/${PENUMBRA_CMAKE_DESTINATION}/PenumbraConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${CMAKE_BINARY_DIR}/${PENUMBRA_CMAKE_DESTINATION}/PenumbraConfig.cmake"
  "${CMAKE_BINARY_DIR}/${PENUMBRA_CMAKE_DESTINATION}/PenumbraConfigVersion.cmake"
  DESTINATION "${PENUMBRA_CMAKE_DESTINATION}"
  COMPONENT   development)
