# cmake -DBUILD_DIR=dir -DTARGET=probe -DEXPECT=pass|missing [-DHEADER=h]
#       -P build_probe.cmake
# Builds one layer probe (tests/cmake/CMakeLists.txt). EXPECT=pass: the build
# must succeed. EXPECT=missing: it must fail, and because HEADER is not found.
cmake_minimum_required(VERSION 3.25)
execute_process(
  COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target ${TARGET}
  RESULT_VARIABLE rc
  OUTPUT_VARIABLE out
  ERROR_VARIABLE out)
if(EXPECT STREQUAL "pass")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${TARGET} should compile but failed (${rc}):\n${out}")
  endif()
elseif(EXPECT STREQUAL "missing")
  string(REPLACE "." "\\." header_re "${HEADER}")
  # GCC: "fatal error: rigel/x/y.h: No such file or directory";
  # Clang: "fatal error: 'rigel/x/y.h' file not found".
  if(rc EQUAL 0)
    message(FATAL_ERROR "${TARGET} compiled, but its include of ${HEADER} is upward and must fail:\n${out}")
  elseif(NOT out MATCHES "${header_re}'?:? (No such file or directory|file not found)")
    message(FATAL_ERROR "${TARGET} failed, but not because ${HEADER} is hidden:\n${out}")
  endif()
else()
  message(FATAL_ERROR "build_probe.cmake: EXPECT is pass or missing, not '${EXPECT}'")
endif()
