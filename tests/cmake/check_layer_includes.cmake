# cmake -DSOURCE_DIR=repo -DLAYERS_FILE=layers.cmake -P check_layer_includes.cmake
# Fails if a file of include/rigel/<L>/ or src/<L>/ includes a header of a
# layer that L does not see. LAYERS_FILE (written at configure time by
# tests/cmake/CMakeLists.txt) sets RIGEL_LAYERS and, per layer,
# RIGEL_LAYER_VISIBLE_<L>.
cmake_minimum_required(VERSION 3.25)
include(${LAYERS_FILE})
set(offences "")
set(checked 0)
foreach(layer IN LISTS RIGEL_LAYERS)
  file(GLOB_RECURSE files
    ${SOURCE_DIR}/include/rigel/${layer}/*.h ${SOURCE_DIR}/src/${layer}/*.h
    ${SOURCE_DIR}/src/${layer}/*.cc)
  foreach(f IN LISTS files)
    math(EXPR checked "${checked} + 1")
    file(STRINGS ${f} lines REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]rigel/")
    foreach(line IN LISTS lines)
      string(REGEX MATCH "[<\"]rigel/([^/>\"]+)/" _ "${line}")
      if(NOT CMAKE_MATCH_1 IN_LIST RIGEL_LAYER_VISIBLE_${layer})
        file(RELATIVE_PATH rel ${SOURCE_DIR} ${f})
        string(STRIP "${line}" line)
        string(APPEND offences "  ${rel}: ${line} (${layer} sees ${RIGEL_LAYER_VISIBLE_${layer}})\n")
      endif()
    endforeach()
  endforeach()
endforeach()
if(checked EQUAL 0)
  message(FATAL_ERROR "no layer files found under ${SOURCE_DIR}")
endif()
if(offences)
  message(FATAL_ERROR "includes of layers not visible from the including layer:\n${offences}")
endif()
message(STATUS "${checked} files of ${RIGEL_LAYERS}: every rigel/ include names a visible layer")
