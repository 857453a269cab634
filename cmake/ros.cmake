# The ROS layer (converts, calls the core façade, publishes), the nodes, ROS tools and ROS tests.

file(GLOB_RECURSE LTM_ROS_SOURCES CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/ros/*.cpp")
add_library(longterm_mapper2d_ros ${LTM_ROS_SOURCES})
target_include_directories(longterm_mapper2d_ros PUBLIC
  "${CMAKE_CURRENT_SOURCE_DIR}/include" ${catkin_INCLUDE_DIRS})
target_link_libraries(longterm_mapper2d_ros PUBLIC longterm_mapper2d_core ${catkin_LIBRARIES})
add_dependencies(longterm_mapper2d_ros ${PROJECT_NAME}_generate_messages_cpp
                 ${catkin_EXPORTED_TARGETS})

# Nodes and ROS tools: src/nodes/<name>_main.cpp and src/tools/ros/<name>_main.cpp.
file(GLOB LTM_ROS_EXECUTABLES CONFIGURE_DEPENDS
  "${CMAKE_CURRENT_SOURCE_DIR}/src/nodes/*_main.cpp"
  "${CMAKE_CURRENT_SOURCE_DIR}/src/tools/ros/*_main.cpp")
foreach(exe_source ${LTM_ROS_EXECUTABLES})
  get_filename_component(exe_name ${exe_source} NAME_WE)
  string(REGEX REPLACE "_main$" "" exe_name ${exe_name})
  add_executable(${exe_name} ${exe_source})
  target_link_libraries(${exe_name} longterm_mapper2d_ros)
  list(APPEND LTM_ROS_EXECUTABLE_TARGETS ${exe_name})
endforeach()
# offline_mapper is the core's offline application given a bag reader.
target_link_libraries(offline_mapper longterm_mapper2d_offline)

# ROS-layer unit tests (no roscore needed).
file(GLOB LTM_ROS_TEST_SOURCES CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/test/ros/*_test.cpp")
if(LTM_ROS_TEST_SOURCES)
  add_executable(test_ros ${LTM_ROS_TEST_SOURCES})
  target_link_libraries(test_ros ${LTM_TEST_SUPPORT} longterm_mapper2d_ros ${LTM_GTEST_LIBS})
  target_include_directories(test_ros PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}/test")
  target_compile_definitions(test_ros PRIVATE
    LTM_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/test/data"
    LTM_SHARED_DATA_DIR="${LTM_SHARED_DATA_DIR}"
    LTM_CONFIG_DIR="${CMAKE_CURRENT_SOURCE_DIR}/config")
  gtest_discover_tests(test_ros DISCOVERY_TIMEOUT 60
    PROPERTIES SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]" LABELS unit)
endif()

# Integration tests with roscore: test/rostest/*.test, run through rostest by CTest. Their test
# scripts go next to the executables, where roslaunch finds nodes of this package. They run alone
# (RUN_SERIAL) under `ctest -j`: their nodes play bags against the wall clock.
file(GLOB LTM_ROSTEST_SCRIPTS CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/test/rostest/*.py")
foreach(script ${LTM_ROSTEST_SCRIPTS})
  get_filename_component(script_name ${script} NAME)
  configure_file(${script} "${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}/${script_name}" COPYONLY)
endforeach()
file(GLOB LTM_ROSTESTS CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/test/rostest/*.test")
foreach(rostest_file ${LTM_ROSTESTS})
  get_filename_component(rostest_name ${rostest_file} NAME_WE)
  add_test(NAME rostest_${rostest_name}
    COMMAND "${CMAKE_CURRENT_SOURCE_DIR}/scripts/run_rostest.sh" "${CATKIN_DEVEL_PREFIX}"
            "${rostest_file}")
  set_tests_properties(rostest_${rostest_name} PROPERTIES LABELS rostest TIMEOUT 1200
                       SKIP_RETURN_CODE 77 RUN_SERIAL TRUE)
endforeach()

install(TARGETS longterm_mapper2d_core longterm_mapper2d_offline longterm_mapper2d_ros ${LTM_ROS_EXECUTABLE_TARGETS}
        ${LTM_CORE_TOOL_TARGETS}
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY include/ DESTINATION ${CATKIN_GLOBAL_INCLUDE_DESTINATION})
install(DIRECTORY launch config rviz DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
