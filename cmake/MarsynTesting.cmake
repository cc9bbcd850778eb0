# marsyn_add_plugin_test(<name> <source>...): a GoogleTest executable for a plugin folder. It
# compiles the plugin's headers directly (src/ on the include path) and links the shared test
# support (randomized enclosure and Jacobian checks).
function(marsyn_add_plugin_test name)
  add_executable(${name} ${ARGN})
  target_include_directories(${name} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src ${PROJECT_SOURCE_DIR}/tests/support)
  target_link_libraries(${name} PRIVATE marsyn::interfaces GTest::gtest_main)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60)
endfunction()
