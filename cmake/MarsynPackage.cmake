# find_package(marsyn) support: marsyn::interfaces, marsyn_add_plugin(), and where plugins go.
include(CMakePackageConfigHelpers)
set(MARSYN_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/marsyn)
install(EXPORT marsynTargets NAMESPACE marsyn:: DESTINATION ${MARSYN_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/marsynConfig.cmake.in
  ${CMAKE_BINARY_DIR}/marsynConfig.cmake INSTALL_DESTINATION ${MARSYN_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/marsynConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/marsynConfig.cmake ${CMAKE_BINARY_DIR}/marsynConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/MarsynPlugin.cmake DESTINATION ${MARSYN_CMAKE_DIR})
