# Installing Penumbra as a library (issue 18): public headers, static libraries, the CMake
# package (lib/cmake/Penumbra: find_package(Penumbra CONFIG COMPONENTS ...) -> Penumbra::<name>)
# and a pkg-config file for the SH library (penumbra-sh.pc). Included by the top-level
# CMakeLists.txt after every library is defined; docs/architecture.md ("Packaging") explains it.
#
# Each library is one package component with its own export set (Penumbra_<name>Targets.cmake),
# so find_package(Penumbra COMPONENTS sh) needs glm only, not Embree or OpenEXR. The components a
# library links and the external packages its exported targets name (PUBLIC, and PRIVATE ones as
# $<LINK_ONLY:...> of a static library) are read from the targets themselves, so the generated
# PenumbraConfig.cmake calls find_dependency for exactly those.
#
# Flags: penumbra_flags (Penumbra::flags) is installed, but only -march reaches consumers (and
# the C++20 requirement); the warnings and the sanitizer's compile flags stay in Penumbra's build.
# -march must propagate: public headers hold 32-byte vector types (sh/lanes.h: Lanes, used by
# inline functions and as members of BlockerLogSum) whose ABI and inline code differ without AVX.
# Not installed: the renderer (penumbra_render, penumbra_render_extract: Vulkan, ImGui and stb
# through pkg-config, compiled shaders), the tools, tests, benchmarks and the game.

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PENUMBRA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Penumbra)

# --- penumbra_flags: build-only warnings, -march for everyone (see above).
get_target_property(_penumbra_opts penumbra_flags INTERFACE_COMPILE_OPTIONS)
set(_penumbra_wrapped)
set(PENUMBRA_CONSUMER_FLAGS)  # what consumers compile with; also goes into penumbra-sh.pc
foreach(opt IN LISTS _penumbra_opts)
  if(opt MATCHES "^-march=")
    list(APPEND _penumbra_wrapped "${opt}")
    list(APPEND PENUMBRA_CONSUMER_FLAGS "${opt}")
  else()
    list(APPEND _penumbra_wrapped "$<BUILD_INTERFACE:${opt}>")
  endif()
endforeach()
set_property(TARGET penumbra_flags PROPERTY INTERFACE_COMPILE_OPTIONS "${_penumbra_wrapped}")
get_target_property(_penumbra_defs penumbra_flags INTERFACE_COMPILE_DEFINITIONS)
if(_penumbra_defs)  # PENUMBRA_TSAN: no public header reads it
  set_property(TARGET penumbra_flags PROPERTY INTERFACE_COMPILE_DEFINITIONS
                                              "$<BUILD_INTERFACE:${_penumbra_defs}>")
endif()
# The sanitizer link flags (sanitized builds only) do propagate: a sanitized static library
# needs the sanitizer's runtime wherever it is linked.
target_compile_features(penumbra_flags INTERFACE cxx_std_20)

# The find_dependency arguments for an external target an installed target links; a new
# dependency must be added here (configure fails, naming it, until it is).
function(_penumbra_package_of target out)
  set(map
    "TBB::tbb=TBB"
    "glm::glm=glm"
    "Threads::Threads=Threads"
    "OpenEXR::OpenEXR=OpenEXR,3,CONFIG"
    "draco::draco=draco,CONFIG"
    "nlohmann_json::nlohmann_json=nlohmann_json,3,CONFIG"
    "meshoptimizer::meshoptimizer=meshoptimizer,CONFIG"
    "embree=embree,3"
    "Eigen3::Eigen=Eigen3,3.3,NO_MODULE")
  foreach(entry IN LISTS map)
    if(entry MATCHES "^([^=]+)=(.*)$" AND CMAKE_MATCH_1 STREQUAL target)
      set(${out} "${CMAKE_MATCH_2}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  message(FATAL_ERROR "cmake/PenumbraInstall.cmake: no package known for '${target}'; add it to "
                      "_penumbra_package_of")
endfunction()

# penumbra_install_component(NAME TARGET): installs TARGET as Penumbra::NAME (EXPORT_NAME NAME)
# with its include/ folder, and records its components and packages for PenumbraConfig.cmake.
# Call in dependency order (a component after the ones it links).
set(PENUMBRA_COMPONENTS)
set(PENUMBRA_COMPONENT_TABLE "")
macro(penumbra_install_component name target)
  _penumbra_install_component(${name} ${target})
  list(APPEND PENUMBRA_COMPONENTS ${name})
  string(APPEND PENUMBRA_COMPONENT_TABLE "${_penumbra_table_line}")
endmacro()
function(_penumbra_install_component name target)
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  install(TARGETS ${target} EXPORT Penumbra_${name}
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  get_target_property(dir ${target} SOURCE_DIR)
  if(EXISTS ${dir}/include)
    install(DIRECTORY ${dir}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
  install(EXPORT Penumbra_${name} NAMESPACE Penumbra:: FILE Penumbra_${name}Targets.cmake
          DESTINATION ${PENUMBRA_INSTALL_CMAKEDIR})

  get_target_property(links ${target} INTERFACE_LINK_LIBRARIES)
  if(NOT links)
    set(links)
  endif()
  set(components)
  set(packages)
  foreach(link IN LISTS links)
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
    if(link MATCHES "^penumbra_")
      get_target_property(export_name ${link} EXPORT_NAME)
      if(NOT export_name OR NOT export_name IN_LIST PENUMBRA_COMPONENTS)
        message(FATAL_ERROR "${target} links ${link}, which is not installed before it")
      endif()
      list(APPEND components ${export_name})
    elseif(link)
      _penumbra_package_of(${link} package)
      list(APPEND packages ${package})
    endif()
  endforeach()
  list(REMOVE_DUPLICATES components)
  list(REMOVE_DUPLICATES packages)
  set(_penumbra_table_line
      "set(_Penumbra_${name}_components ${components})\nset(_Penumbra_${name}_packages ${packages})\n"
      PARENT_SCOPE)
endfunction()

# Dependency order. flags first: every library links it.
penumbra_install_component(flags penumbra_flags)
penumbra_install_component(data penumbra_data)
penumbra_install_component(sh penumbra_sh)
penumbra_install_component(ecs penumbra_ecs)
penumbra_install_component(jobs penumbra_jobs)
penumbra_install_component(components penumbra_components)
penumbra_install_component(assets penumbra_assets)
penumbra_install_component(reference penumbra_reference)
penumbra_install_component(scene penumbra_scene)
penumbra_install_component(terrain_shadow penumbra_terrain_shadow)
penumbra_install_component(blocker_accumulation penumbra_blocker_accumulation)
penumbra_install_component(spherical_lights penumbra_spherical_lights)
penumbra_install_component(probe_cloud penumbra_probe_cloud)
penumbra_install_component(environment penumbra_environment)
penumbra_install_component(probe_bake penumbra_probe_bake)

# --- The package: PenumbraConfig.cmake (from PenumbraConfig.cmake.in) and the version file.
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/PenumbraConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/PenumbraConfig.cmake
                              INSTALL_DESTINATION ${PENUMBRA_INSTALL_CMAKEDIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/PenumbraConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/PenumbraConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/PenumbraConfigVersion.cmake
        DESTINATION ${PENUMBRA_INSTALL_CMAKEDIR})

# --- pkg-config for the SH library, relocatable (prefix from the .pc file's own folder).
set(PENUMBRA_PKGCONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
file(RELATIVE_PATH PENUMBRA_PC_PREFIX_REL /root/${PENUMBRA_PKGCONFIG_DIR} /root)  # ../..
string(REGEX REPLACE "/$" "" PENUMBRA_PC_PREFIX_REL "${PENUMBRA_PC_PREFIX_REL}")
list(JOIN PENUMBRA_CONSUMER_FLAGS " " PENUMBRA_PC_CFLAGS)
configure_file(${CMAKE_CURRENT_LIST_DIR}/penumbra-sh.pc.in ${CMAKE_CURRENT_BINARY_DIR}/penumbra-sh.pc
               @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/penumbra-sh.pc DESTINATION ${PENUMBRA_PKGCONFIG_DIR})
