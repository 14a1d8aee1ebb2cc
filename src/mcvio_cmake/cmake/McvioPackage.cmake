# mcvio package conventions: C++17, warnings on, Release by default, exported CMake configs,
# GoogleTest through ctest. Every mcvio package does find_package(mcvio_cmake REQUIRED).
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()
set(CMAKE_CXX_STANDARD 17)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)
# Installed programs find the libraries of the other mcvio packages (colcon installs each package
# in its own prefix) without LD_LIBRARY_PATH.
set(CMAKE_INSTALL_RPATH "$ORIGIN/../lib")
set(CMAKE_INSTALL_RPATH_USE_LINK_PATH ON)
option(MCVIO_BUILD_TESTS "Build the package's tests" ON)
option(MCVIO_BUILD_BENCHMARKS "Build the package's Google Benchmarks" ON)
option(MCVIO_WERROR "Treat warnings as errors" OFF)
if(MCVIO_BUILD_TESTS)
  # CTest (not just enable_testing) writes the DartConfiguration colcon's ctest call expects.
  include(CTest)
endif()

# mcvio_add_library(NAME SOURCES src... PUBLIC_DEPS targets... PRIVATE_DEPS targets...)
# Builds a shared library whose headers live in include/, installs and exports it as mcvio::NAME.
function(mcvio_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${name} SHARED ${ARG_SOURCES})
  add_library(mcvio::${name} ALIAS ${name})
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  mcvio_set_warnings(${name})
  install(TARGETS ${name} EXPORT ${PROJECT_NAME}Targets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()

function(mcvio_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(MCVIO_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# mcvio_export_package(DEPENDENCIES pkg1 pkg2 ...)
# Writes <project>Config.cmake that finds the listed dependencies and imports mcvio::targets.
function(mcvio_export_package)
  cmake_parse_arguments(ARG "" "" "DEPENDENCIES" ${ARGN})
  set(dest ${CMAKE_INSTALL_DATADIR}/${PROJECT_NAME}/cmake)
  install(EXPORT ${PROJECT_NAME}Targets NAMESPACE mcvio:: DESTINATION ${dest})
  set(content "include(CMakeFindDependencyMacro)\n")
  foreach(dep IN LISTS ARG_DEPENDENCIES)
    string(APPEND content "find_dependency(${dep})\n")
  endforeach()
  string(APPEND content "include(\${CMAKE_CURRENT_LIST_DIR}/${PROJECT_NAME}Targets.cmake)\n")
  file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/${PROJECT_NAME}Config.cmake "${content}")
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/${PROJECT_NAME}Config.cmake DESTINATION ${dest})
endfunction()

# mcvio_add_gtest(NAME SOURCES src... LIBS targets...)
# One GoogleTest executable; each TEST becomes a ctest case (discovered when ctest runs).
function(mcvio_add_gtest name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;LIBS" ${ARGN})
  find_package(GTest REQUIRED)
  include(GoogleTest)
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  mcvio_set_warnings(${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  # Tests find ../shared/data through this variable and skip cleanly when it is absent.
  get_filename_component(shared_dir "${MCVIO_REPO_ROOT}/../shared" ABSOLUTE)
  # Listing the tests loads Fast DDS and OpenCV; CMake's 5 s default once timed out on a busy
  # host and dropped a whole package's tests.
  gtest_discover_tests(${name} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
    PROPERTIES TIMEOUT ${ARG_TIMEOUT}
    ENVIRONMENT "MCVIO_SHARED_DIR=${shared_dir}")
endfunction()

# mcvio_add_benchmark(NAME SOURCES src... LIBS targets...): a Google Benchmark, never run by ctest.
function(mcvio_add_benchmark name)
  if(NOT MCVIO_BUILD_BENCHMARKS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  find_package(benchmark REQUIRED)
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} benchmark::benchmark)
  mcvio_set_warnings(${name})
  install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_LIBDIR}/${PROJECT_NAME})
endfunction()

# The repository root, so tests can locate ../shared next to a clean clone.
if(NOT MCVIO_REPO_ROOT)
  set(_dir ${CMAKE_CURRENT_SOURCE_DIR})
  while(NOT EXISTS ${_dir}/colcon.meta AND NOT _dir STREQUAL "/")
    get_filename_component(_dir ${_dir} DIRECTORY)
  endwhile()
  set(MCVIO_REPO_ROOT ${_dir})
endif()
