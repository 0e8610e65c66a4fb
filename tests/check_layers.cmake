# The layer rule of docs/design.md, checked on every header: a module's
# headers include only its own layer's modules and those below, and a
# capability only the capabilities the table names.
#
#   cmake -DINCLUDE_DIR=<repo>/include -P check_layers.cmake
#
# Fails naming each header and the include that breaks the rule, and any
# module the table below does not know (a new folder needs its layer).

cmake_minimum_required(VERSION 3.21)

set(numeric rotation optimize maxflow poisson image)
set(clip_model motion bvh)
set(below_capabilities core ${numeric} ${clip_model})

set(allowed_core "")
foreach(m IN LISTS numeric)
  set(allowed_${m} core)
endforeach()
set(allowed_motion core rotation)
set(allowed_bvh core rotation motion)
set(allowed_ik ${below_capabilities})
set(allowed_sadm ${below_capabilities})
set(allowed_flight ${below_capabilities})
# The capabilities that plant feet use ik/; the texture mixes in symmetric
# playback.
set(allowed_transition ${below_capabilities} ik)
set(allowed_symmetry ${below_capabilities} ik)
set(allowed_texture ${below_capabilities} ik symmetry)

if(NOT INCLUDE_DIR)
  message(FATAL_ERROR "check_layers.cmake: pass -DINCLUDE_DIR=<the repository's include folder>")
endif()

set(problems "")
set(checked 0)
file(GLOB module_dirs LIST_DIRECTORIES true "${INCLUDE_DIR}/anima/*")
foreach(dir IN LISTS module_dirs)
  if(NOT IS_DIRECTORY "${dir}")
    continue()
  endif()
  get_filename_component(module "${dir}" NAME)
  if(NOT DEFINED allowed_${module})
    string(APPEND problems "  module '${module}' has no layer in check_layers.cmake (see docs/design.md)\n")
    continue()
  endif()
  file(GLOB_RECURSE headers "${dir}/*.hpp")
  foreach(header IN LISTS headers)
    math(EXPR checked "${checked} + 1")
    file(STRINGS "${header}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*<anima/")
    foreach(line IN LISTS includes)
      # <anima/X/...> and the umbrella <anima/X.hpp> both name module X.
      if(NOT line MATCHES "<anima/([a-z_]+)[/.]")
        continue()
      endif()
      set(used "${CMAKE_MATCH_1}")
      if(used STREQUAL module)
        continue()
      endif()
      if(NOT used IN_LIST allowed_${module})
        file(RELATIVE_PATH shown "${INCLUDE_DIR}" "${header}")
        string(STRIP "${line}" line)
        string(APPEND problems "  ${shown}: '${line}': ${module}/ may not include ${used}/\n")
      endif()
    endforeach()
  endforeach()
endforeach()

if(checked EQUAL 0)
  message(FATAL_ERROR "check_layers.cmake: no header found under ${INCLUDE_DIR}/anima")
endif()
if(problems)
  message(FATAL_ERROR "headers that break the layer rule of docs/design.md:\n${problems}")
endif()
message(STATUS "${checked} headers keep to their layers")
