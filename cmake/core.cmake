# The ROS-free core: algorithm library, ROS-free tools and the core unit tests.
# Never give these targets catkin include directories: a ROS include in the core must fail to build.

file(GLOB_RECURSE LTM_CORE_SOURCES CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/core/*.cpp")
add_library(longterm_mapper2d_core ${LTM_CORE_SOURCES})
target_include_directories(longterm_mapper2d_core PUBLIC
  $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
target_link_libraries(longterm_mapper2d_core PUBLIC Eigen3::Eigen Ceres::ceres yaml-cpp PNG::PNG
                      Threads::Threads)
set_target_properties(longterm_mapper2d_core PROPERTIES POSITION_INDEPENDENT_CODE ON)

# ROS-free command-line tools: src/tools/core/<name>_main.cpp -> executable <name>.
file(GLOB LTM_CORE_TOOLS CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/tools/core/*_main.cpp")
foreach(tool_source ${LTM_CORE_TOOLS})
  get_filename_component(tool_name ${tool_source} NAME_WE)
  string(REGEX REPLACE "_main$" "" tool_name ${tool_name})
  add_executable(${tool_name} ${tool_source})
  target_link_libraries(${tool_name} longterm_mapper2d_core)
  list(APPEND LTM_CORE_TOOL_TARGETS ${tool_name})
endforeach()

# The offline mapper's application (command line, CARMEN input, outputs) is ROS-free; the ROS build
# links it with a bag reader (src/nodes/offline_mapper_main.cpp), the ROS-free build reads CARMEN
# logs only, so the real-data tier also runs in a plain-CMake (sanitized) build.
file(GLOB LTM_OFFLINE_SOURCES CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/tools/offline/*.cpp")
list(FILTER LTM_OFFLINE_SOURCES EXCLUDE REGEX "_main\\.cpp$")
add_library(longterm_mapper2d_offline ${LTM_OFFLINE_SOURCES})
target_link_libraries(longterm_mapper2d_offline PUBLIC longterm_mapper2d_core)
if(LTM_CORE_ONLY)
  add_executable(offline_mapper
                 "${CMAKE_CURRENT_SOURCE_DIR}/src/tools/offline/ros_free_offline_mapper_main.cpp")
  target_link_libraries(offline_mapper longterm_mapper2d_offline)
  list(APPEND LTM_CORE_TOOL_TARGETS offline_mapper)
endif()

# GoogleTest: catkin brings its own gtest targets; plain CMake uses the system package.
if(TARGET gtest_main)
  set(LTM_GTEST_LIBS gtest_main gtest)
else()
  find_package(GTest REQUIRED)
  set(LTM_GTEST_LIBS GTest::gtest_main GTest::gtest)
endif()
include(GoogleTest)

# Adds one gtest executable per test folder; each TEST becomes its own CTest test. Tests that call
# GTEST_SKIP are reported as skipped by CTest.
function(ltm_add_gtest_dir dir target)
  file(GLOB sources CONFIGURE_DEPENDS "${dir}/*_test.cpp")
  if(NOT sources)
    return()
  endif()
  add_executable(${target} ${sources})
  target_link_libraries(${target} ${ARGN} longterm_mapper2d_core ${LTM_GTEST_LIBS})
  target_include_directories(${target} PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}/test")
  target_compile_definitions(${target} PRIVATE
    LTM_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/test/data"
    LTM_SHARED_DATA_DIR="${LTM_SHARED_DATA_DIR}"
    LTM_CONFIG_DIR="${CMAKE_CURRENT_SOURCE_DIR}/config")
  gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60
    PROPERTIES SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]" LABELS unit)
endfunction()

# Test helpers shared by several test folders (synthetic worlds and the like), compiled once.
file(GLOB LTM_TEST_SUPPORT_SOURCES CONFIGURE_DEPENDS
  "${CMAKE_CURRENT_SOURCE_DIR}/test/testing/*.cpp")
add_library(longterm_mapper2d_test_support STATIC ${LTM_TEST_SUPPORT_SOURCES})
target_link_libraries(longterm_mapper2d_test_support PUBLIC longterm_mapper2d_core ${LTM_GTEST_LIBS})
target_include_directories(longterm_mapper2d_test_support PUBLIC
  "${CMAKE_CURRENT_SOURCE_DIR}/test")
set(LTM_TEST_SUPPORT longterm_mapper2d_test_support)

file(GLOB LTM_CORE_TEST_DIRS LIST_DIRECTORIES true "${CMAKE_CURRENT_SOURCE_DIR}/test/core/*")
foreach(dir ${LTM_CORE_TEST_DIRS})
  if(IS_DIRECTORY ${dir})
    get_filename_component(module ${dir} NAME)
    ltm_add_gtest_dir(${dir} test_core_${module} ${LTM_TEST_SUPPORT})
  endif()
endforeach()

# The offline mapper's application pieces (ROS-free).
ltm_add_gtest_dir("${CMAKE_CURRENT_SOURCE_DIR}/test/tools/offline" test_tools_offline
                  longterm_mapper2d_offline)

# A short libFuzzer run over the file parsers (scripts/fuzz.sh builds the targets in
# test/fuzz/ with clang, ASan and UBSan; longer runs by hand: scripts/fuzz.sh --seconds 600).
find_program(LTM_CLANGXX clang++)
if(LTM_CLANGXX)
  add_test(NAME fuzz_parsers
           COMMAND bash "${CMAKE_CURRENT_SOURCE_DIR}/scripts/fuzz.sh" --seconds 10)
  set_tests_properties(fuzz_parsers PROPERTIES LABELS fuzz TIMEOUT 900)
else()
  message(STATUS "clang++ not found: the fuzz test is not registered (scripts/install_deps.sh)")
endif()
