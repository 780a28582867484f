# The installed package end to end (ctest -L package; issue 18): installs the build tree into a
# fresh prefix, checks that no installed CMake file points into the source tree, builds
# examples/host_engine against the prefix alone and runs it, and asks pkg-config for penumbra-sh.
#   cmake -DBUILD_DIR=<build tree> -DSOURCE_DIR=<source tree> -DWORK_DIR=<scratch folder>
#         -DCXX=<compiler> -DGENERATOR=<generator> -P install_and_build_example.cmake
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR CXX GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_and_build_example.cmake: -D${var}=... missing")
  endif()
endforeach()
set(prefix ${WORK_DIR}/prefix)
set(example_build ${WORK_DIR}/host_engine)
file(REMOVE_RECURSE ${WORK_DIR})

# run(step COMMAND...): runs the command, prints its output, stops the test when it fails.
function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  message("-- ${step}:\n${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${step} failed (${rc})")
  endif()
endfunction()

run("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

file(GLOB_RECURSE installed_cmake ${prefix}/*.cmake ${prefix}/*.pc)
foreach(f IN LISTS installed_cmake)
  file(READ ${f} text)
  foreach(dir engine components systems)
    string(FIND "${text}" "${SOURCE_DIR}/${dir}/" at)
    if(at GREATER -1)
      message(FATAL_ERROR "${f} points into the source tree (${SOURCE_DIR}/${dir}/)")
    endif()
  endforeach()
endforeach()

# The example sees the prefix and the system's packages, nothing of Penumbra's trees.
run("configure examples/host_engine" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/host_engine
    -B ${example_build} -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
file(STRINGS ${example_build}/CMakeCache.txt penumbra_dir REGEX "^Penumbra_DIR:")
if(NOT penumbra_dir MATCHES "=${prefix}/")
  message(FATAL_ERROR "the example found Penumbra outside the prefix: ${penumbra_dir}")
endif()
run("build examples/host_engine" ${CMAKE_COMMAND} --build ${example_build})
run("run host_engine" ${example_build}/host_engine)

# pkg-config for the SH library (only where pkg-config is installed: it is in ./penumbra's list).
find_program(PKG_CONFIG pkg-config)
if(PKG_CONFIG)
  file(GLOB_RECURSE pc_file ${prefix}/penumbra-sh.pc)
  get_filename_component(pc_dir "${pc_file}" DIRECTORY)
  set(ENV{PKG_CONFIG_PATH} ${pc_dir})
  run("pkg-config penumbra-sh" ${PKG_CONFIG} --cflags --libs penumbra-sh)
endif()
