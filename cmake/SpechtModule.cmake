# specht_module(<name> [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# One static library per module: public headers in include/specht/<name>/,
# sources in src/ (and src/internal/ for private helpers). Alias specht::<name>.
function(specht_module name)
  cmake_parse_arguments(M "" "" "PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp")
  add_library(specht_${name} STATIC ${sources})
  add_library(specht::${name} ALIAS specht_${name})
  target_include_directories(specht_${name}
    PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}/include"
    PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}/src")
  target_link_libraries(specht_${name} PUBLIC ${M_PUBLIC_DEPS} PRIVATE ${M_PRIVATE_DEPS} specht_build_flags)
endfunction()

# specht_test(<name> SOURCES ... LIBS ... [LABELS ...])
# A gtest executable; every test case becomes a ctest entry carrying the labels.
# Where data, sources and the binary are is compiled into tests/support (and can be
# overridden by the SPECHT_DATA_DIR, SPECHT_SOURCE_DIR, SPECHT_BINARY variables).
function(specht_test name)
  cmake_parse_arguments(T "" "" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gmock GTest::gtest GTest::gtest_main specht_build_flags specht_glue_flags)
  if(NOT T_LABELS)
    set(T_LABELS fast)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${T_LABELS}")
endfunction()
