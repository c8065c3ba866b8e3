# `cmake --install build [--prefix DIR]`: the C++ package. Installs the public headers, the
# libraries (static, position-independent), the `skin` executable, the data tables and a CMake
# package: find_package(SpectralSkin CONFIG) gives SpectralSkin::util, ::physics, ::transport,
# ::color, ::model and, when built, ::mc, ::image, ::fit, ::render, ::batch, ::export, each with its
# dependencies (Debian's libraries, found by the package's config file). The physical tables
# are compiled into the libraries (SpectralSkin::embedded_data), so nothing is read at run time;
# data/*.csv are installed beside for their sources and units.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(skin_install_parts "")
set(skin_install_targets skin_embedded_data skin_warnings skin_sanitize)
foreach(part util physics transport color model mc image fit render batch export)
  if(TARGET skin_${part})
    list(APPEND skin_install_parts ${part})
    list(APPEND skin_install_targets skin_${part})
  endif()
endforeach()
foreach(t ${skin_install_targets})
  string(REGEX REPLACE "^skin_" "" name ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${name})
endforeach()

install(TARGETS ${skin_install_targets} EXPORT SpectralSkinTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS skin RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The headers of the libraries installed (include/skin/<part>/).
foreach(part ${skin_install_parts})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/skin/${part}
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/skin)
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/spectral_skin/data
  FILES_MATCHING PATTERN "*.csv")

# Every imported target that an installed library links (privately too: static libraries pass
# them on) must be found by the package's config file; checked here, at configure time, so that
# a new dependency cannot be forgotten there. skin::render links tinyobjloader's imported target
# when its CMake package exists (src/render/CMakeLists.txt), the plain library otherwise.
file(READ ${PROJECT_SOURCE_DIR}/cmake/SpectralSkinConfig.cmake.in skin_config_text)
set(skin_render_tinyobjloader_package FALSE)
foreach(t ${skin_install_targets})
  get_target_property(libs ${t} LINK_LIBRARIES)
  if(NOT libs)
    continue()
  endif()
  foreach(lib ${libs})
    if(lib MATCHES "^([A-Za-z0-9_]+)::" AND NOT CMAKE_MATCH_1 STREQUAL "skin")
      if(CMAKE_MATCH_1 STREQUAL "tinyobjloader")
        set(skin_render_tinyobjloader_package TRUE)
      endif()
      string(FIND "${skin_config_text}" "find_dependency(${CMAKE_MATCH_1}" at)
      if(at EQUAL -1)
        message(FATAL_ERROR "${t} links ${lib}: cmake/SpectralSkinConfig.cmake.in needs "
          "find_dependency(${CMAKE_MATCH_1}) for consumers of the installed package")
      endif()
    endif()
  endforeach()
endforeach()
set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/SpectralSkin)
install(EXPORT SpectralSkinTargets NAMESPACE SpectralSkin:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/SpectralSkinConfig.cmake.in
  ${CMAKE_BINARY_DIR}/SpectralSkinConfig.cmake INSTALL_DESTINATION ${config_dir})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/SpectralSkinConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/SpectralSkinConfig.cmake
  ${CMAKE_BINARY_DIR}/SpectralSkinConfigVersion.cmake DESTINATION ${config_dir})
