# Compiles one stage of a GLSL file to SPIR-V as a C header (used by engine/render's build and
# by the shader-error test). Arguments (-D): GLSLANG, SOURCE, STAGE (vert|frag), NAME (C array
# name), DEFINES (comma separated, may be empty), OUTPUT.
#
# Every stage is compiled with -DPENUMBRA_VERTEX or -DPENUMBRA_FRAGMENT, so one file holds a
# pass's stages. On failure the message names the shader file and line ("<file>:<line>: ...")
# and the build stops.
cmake_minimum_required(VERSION 3.25)
if(STAGE STREQUAL "vert")
  set(stage_define PENUMBRA_VERTEX)
elseif(STAGE STREQUAL "frag")
  set(stage_define PENUMBRA_FRAGMENT)
else()
  message(FATAL_ERROR "compile_shader: unknown STAGE '${STAGE}'")
endif()
set(args -V --target-env vulkan1.3 -S ${STAGE} -D${stage_define} --vn ${NAME} -o ${OUTPUT})
if(DEFINES)
  string(REPLACE "," ";" define_list "${DEFINES}")
  foreach(d ${define_list})
    list(APPEND args -D${d})
  endforeach()
endif()
execute_process(COMMAND ${GLSLANG} ${args} ${SOURCE}
                RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT result EQUAL 0)
  # glslang prints "ERROR: <file>:<line>: <message>"; keep those lines, drop the noise.
  string(REGEX MATCHALL "ERROR: [^\n]*" errors "${out}\n${err}")
  set(text "")
  foreach(e ${errors})
    string(REGEX REPLACE "^ERROR: " "" e "${e}")
    if(NOT e MATCHES "compilation errors" AND NOT e MATCHES "^[0-9]+ compilation")
      string(APPEND text "  ${e}\n")
    endif()
  endforeach()
  if(text STREQUAL "")
    set(text "${out}${err}")
  endif()
  file(REMOVE ${OUTPUT})
  message(FATAL_ERROR "shader compile failed (${STAGE}${DEFINES}): ${SOURCE}\n${text}")
endif()
