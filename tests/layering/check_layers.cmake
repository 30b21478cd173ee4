# Checks the engine's layering (docs/architecture.md): every #include "engine/<folder>/..." in a
# file under ROOT/engine/<own>/ must name <own> or a folder that <own> uses (its DEPS in
# engine/layers.cmake, and theirs). A folder above its own layer, or one it does not list, is an
# error naming the file and the include line; the exit status is then non-zero.
#   cmake -DROOT=<repository root> [-DLAYERS=<layers.cmake>] -P tests/layering/check_layers.cmake
# Run by CTest as engine_layering; engine_layering_catches_upward runs it on a fixture with one
# upward include and expects it to fail.
cmake_minimum_required(VERSION 3.25)  # script mode: IN_LIST and the other current policies
if(NOT ROOT)
  message(FATAL_ERROR "usage: cmake -DROOT=<repository root> [-DLAYERS=<file>] -P check_layers.cmake")
endif()
if(NOT LAYERS)
  set(LAYERS ${ROOT}/engine/layers.cmake)
endif()
get_filename_component(ROOT "${ROOT}" ABSOLUTE)  # a relative ROOT (-DROOT=.) globs from here
include(${LAYERS})

set(errors 0)
set(checked 0)
file(GLOB_RECURSE files RELATIVE ${ROOT} ${ROOT}/engine/*.h ${ROOT}/engine/*.cpp)
list(SORT files)
foreach(f ${files})
  string(REGEX REPLACE "^engine/([^/]+)/.*" "\\1" own "${f}")
  if(own STREQUAL f)
    continue()  # a file directly in engine/ (none today) belongs to no layer
  endif()
  if(NOT own IN_LIST PROSTATESIM_ENGINE_LAYERS)
    message(SEND_ERROR "${f}: engine/${own}/ is not a layer of engine/layers.cmake")
    math(EXPR errors "${errors} + 1")
    continue()
  endif()
  prostatesim_engine_reachable(${own} allowed)
  file(STRINGS ${ROOT}/${f} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"engine/[^/\"]+/")
  foreach(line ${includes})
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"engine/([^/\"]+)/.*" "\\1" target "${line}")
    math(EXPR checked "${checked} + 1")
    if(NOT target IN_LIST allowed)
      string(STRIP "${line}" line)
      message(SEND_ERROR "${f}: ${line}: engine/${own}/ may include only ${allowed} (engine/layers.cmake)")
      math(EXPR errors "${errors} + 1")
    endif()
  endforeach()
endforeach()
list(LENGTH files nfiles)
if(nfiles EQUAL 0)
  message(FATAL_ERROR "no source files under ${ROOT}: not the repository root?")
endif()
if(errors GREATER 0)
  message(FATAL_ERROR "${errors} include(s) against the engine's layering (docs/architecture.md)")
endif()
message(STATUS "engine layering: ${checked} #include \"engine/...\" lines in ${nfiles} files, none above its layer")
