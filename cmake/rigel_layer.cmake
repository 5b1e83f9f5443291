# rigel_layer(NAME SOURCES... DEPS layer...)
# Declares one layer library: public headers in include/rigel/<name>/,
# sources in src/<name>/. DEPS names the layers (and packages) it may use;
# a layer named there (rigel::<layer>) must be declared before.
#
# A layer sees only its own headers and those of the layers below it that
# it depends on, directly or through them: its sources compile against
# ${CMAKE_BINARY_DIR}/layer_include/<name>/, which holds one symbolic link
# rigel/<layer> -> include/rigel/<layer> for exactly those layers. A lower
# layer including a higher layer's header therefore fails to compile
# (tests/cmake shows it). Targets that are not layers (the drivers, tests,
# tools, benchmarks) see all of include/ through any layer they link.
function(rigel_layer name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  set(visible ${name})
  foreach(dep IN LISTS ARG_DEPS)
    if(dep MATCHES "^rigel::(.+)$")
      if(NOT TARGET rigel_${CMAKE_MATCH_1})
        message(FATAL_ERROR "rigel_layer(${name}): ${dep} is not declared yet; declare the layers bottom up")
      endif()
      get_target_property(dep_visible rigel_${CMAKE_MATCH_1} RIGEL_LAYER_VISIBLE)
      list(APPEND visible ${dep_visible})
    endif()
  endforeach()
  list(REMOVE_DUPLICATES visible)
  _rigel_layer_include_tree(${name} "${visible}")

  add_library(rigel_${name} ${ARG_SOURCES})
  add_library(rigel::${name} ALIAS rigel_${name})
  set_property(GLOBAL APPEND PROPERTY RIGEL_LAYERS ${name})
  # The layers it sees, itself first: the layers above it start from this
  # list, and tests/cmake checks every rigel/ include against it.
  set_target_properties(rigel_${name} PROPERTIES RIGEL_LAYER_VISIBLE "${visible}")
  # A layer compiles against its tree; of the layers it links, it gets no
  # include directory (RIGEL_LAYER), while every other consumer gets include/.
  set_target_properties(rigel_${name} PROPERTIES RIGEL_LAYER TRUE)
  target_include_directories(rigel_${name}
    PRIVATE ${CMAKE_BINARY_DIR}/layer_include/${name}
    INTERFACE
    $<$<NOT:$<BOOL:$<TARGET_PROPERTY:RIGEL_LAYER>>>:${PROJECT_SOURCE_DIR}/include>)
  target_link_libraries(rigel_${name} PUBLIC ${ARG_DEPS} PRIVATE rigel_warnings)
endfunction()

# The tree of links for one layer, brought to exactly `visible` on every
# configure: links to layers no longer visible are removed, missing ones
# made, ones pointing elsewhere (a moved source tree) made again.
function(_rigel_layer_include_tree name visible)
  set(root ${CMAKE_BINARY_DIR}/layer_include/${name}/rigel)
  file(MAKE_DIRECTORY ${root})
  file(GLOB present LIST_DIRECTORIES true RELATIVE ${root} ${root}/*)
  foreach(entry IN LISTS present)
    if(NOT entry IN_LIST visible)
      file(REMOVE ${root}/${entry})  # a link: removes the link, not its target
    endif()
  endforeach()
  foreach(layer IN LISTS visible)
    set(headers ${PROJECT_SOURCE_DIR}/include/rigel/${layer})
    if(NOT IS_DIRECTORY ${headers})
      continue()
    endif()
    if(IS_SYMLINK ${root}/${layer})
      file(READ_SYMLINK ${root}/${layer} current)
      if(current STREQUAL headers)
        continue()
      endif()
      file(REMOVE ${root}/${layer})
    endif()
    file(CREATE_LINK ${headers} ${root}/${layer} SYMBOLIC)
  endforeach()
endfunction()
