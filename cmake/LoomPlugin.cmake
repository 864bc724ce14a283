# loom_add_plugin(NAME SOURCES a.cpp b.cpp ... [LIBRARIES targets...]
#                 [TESTS a_test.cpp ... [TEST_LIBRARIES targets...]] [NO_INSTALL])
#
# Builds libloom_NAME.so into LOOM_PLUGIN_OUTPUT_DIR with hidden visibility,
# and writes its manifest libloom_NAME.loom.json beside it by asking the
# `loom` runner to load it: the manifest lets a run load only the plugins its
# graph uses. Works in the Loom tree and, after find_package(loom), outside it.
#
# TESTS builds the GoogleTest program loom_NAME_tests from those sources,
# linked with loom::testing (which finds this build's plugins by itself) and
# GTest::gtest_main, and registers each of its tests with ctest as NAME.<test>
# (call enable_testing() first, in the top-level CMakeLists.txt).
# Set LOOM_PLUGIN_TESTS to OFF to skip them (the Loom tree does when
# LOOM_BUILD_TESTS is OFF).
function(loom_add_plugin name)
  cmake_parse_arguments(ARG "NO_INSTALL" "" "SOURCES;LIBRARIES;TESTS;TEST_LIBRARIES" ${ARGN})
  set(target loom_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE loom::loom ${ARG_LIBRARIES})
  if(NOT LOOM_PLUGIN_OUTPUT_DIR)
    set(LOOM_PLUGIN_OUTPUT_DIR "${CMAKE_BINARY_DIR}/lib/loom/plugins")
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX "lib"
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    LIBRARY_OUTPUT_DIRECTORY "${LOOM_PLUGIN_OUTPUT_DIR}"
    BUILD_RPATH "$ORIGIN/../.."
    INSTALL_RPATH "$ORIGIN/../..")
  if(TARGET loom-runner)
    add_dependencies(${target} loom-runner)
  endif()
  set(manifest "${LOOM_PLUGIN_OUTPUT_DIR}/libloom_${name}.loom.json")
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND loom::runner plugins --manifest "$<TARGET_FILE:${target}>" --output "${manifest}"
    COMMENT "Writing the manifest of plugin ${name}"
    VERBATIM)
  if(NOT ARG_NO_INSTALL)
    install(TARGETS ${target} LIBRARY DESTINATION lib/loom/plugins)
    install(FILES "${manifest}" DESTINATION lib/loom/plugins)
  endif()
  if(ARG_TESTS AND (NOT DEFINED LOOM_PLUGIN_TESTS OR LOOM_PLUGIN_TESTS))
    if(NOT TARGET GTest::gtest_main)
      find_package(GTest)
      if(NOT GTest_FOUND)
        message(FATAL_ERROR "loom_add_plugin(${name} TESTS ...) needs GoogleTest: install it "
                            "(Debian: libgtest-dev) or drop TESTS")
      endif()
    endif()
    if(NOT CMAKE_TESTING_ENABLED)
      message(WARNING "loom_add_plugin(${name} TESTS ...): call enable_testing() in your top-level "
                      "CMakeLists.txt before it, or ctest will not see the tests")
    endif()
    include(GoogleTest)
    add_executable(${target}_tests ${ARG_TESTS})
    target_link_libraries(${target}_tests PRIVATE loom::testing ${ARG_LIBRARIES} ${ARG_TEST_LIBRARIES}
                                                  GTest::gtest_main)
    target_compile_definitions(${target}_tests PRIVATE LOOM_TESTING_PLUGIN_DIR="${LOOM_PLUGIN_OUTPUT_DIR}")
    add_dependencies(${target}_tests ${target})
    gtest_discover_tests(${target}_tests TEST_PREFIX "${name}." DISCOVERY_TIMEOUT 60)
  endif()
endfunction()

# loom_add_plugin_library(NAME SOURCES a.cpp ... [PUBLIC targets...] [PRIVATE targets...])
#
# A plugin's algorithm as a static library that the plugin, its tests and its
# benchmark share: position-independent and built with hidden visibility, so
# the plugin still exports nothing but its entry point. Its folder is on the
# include path of whatever links it.
function(loom_add_plugin_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}")
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
  set_target_properties(${name} PROPERTIES
    POSITION_INDEPENDENT_CODE ON
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
endfunction()
