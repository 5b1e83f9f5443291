# rigel_layer(NAME SOURCES... DEPS layer...)
# Declares one layer library: public headers in include/rigel/<name>/,
# sources in src/<name>/. DEPS names the layers (and packages) it may use.
function(rigel_layer name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(rigel_${name} ${ARG_SOURCES})
  add_library(rigel::${name} ALIAS rigel_${name})
  target_include_directories(rigel_${name} PUBLIC ${PROJECT_SOURCE_DIR}/include)
  target_link_libraries(rigel_${name} PUBLIC ${ARG_DEPS} PRIVATE rigel_warnings)
endfunction()
