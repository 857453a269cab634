# Real-data tier: runs the built executables on ../shared/data. Each test skips itself (with the
# reason) unless LTM_REAL_DATA=1 and the data folder exists; scripts/test.sh sets it under CI=true.
file(GLOB LTM_REAL_DATA_TEST_SOURCES CONFIGURE_DEPENDS
  "${CMAKE_CURRENT_SOURCE_DIR}/test/real_data/*_test.cpp")
if(LTM_REAL_DATA_TEST_SOURCES)
  add_executable(test_real_data ${LTM_REAL_DATA_TEST_SOURCES})
  target_link_libraries(test_real_data ${LTM_TEST_SUPPORT} longterm_mapper2d_core ${LTM_GTEST_LIBS})
  target_include_directories(test_real_data PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}/test")
  target_compile_definitions(test_real_data PRIVATE
    LTM_SHARED_DATA_DIR="${LTM_SHARED_DATA_DIR}"
    LTM_BIN_DIR="$<TARGET_FILE_DIR:offline_mapper>"
    LTM_CONFIG_DIR="${CMAKE_CURRENT_SOURCE_DIR}/config")
  if(NOT LTM_CORE_ONLY)
    # Logs are read from their bags; the ROS-free build reads the CARMEN copies of the same logs.
    target_compile_definitions(test_real_data PRIVATE LTM_READS_BAGS=1)
  endif()
  add_dependencies(test_real_data ${LTM_ROS_EXECUTABLE_TARGETS} ${LTM_CORE_TOOL_TARGETS})
  gtest_discover_tests(test_real_data DISCOVERY_TIMEOUT 60
    PROPERTIES SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]" LABELS real_data TIMEOUT 1800)
endif()
