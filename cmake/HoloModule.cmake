# Warnings for every target of the project; -Werror when HOLO_WERROR is on (CI).
function(holo_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                                           -Wnon-virtual-dtor -Wcast-align -Wunused)
  if(HOLO_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# holo_uses_std_regex(TARGET): GCC 12 misreads libstdc++'s std::regex as using uninitialised
# memory once ASan instruments it (-Wmaybe-uninitialized inside std::function); such targets keep
# every other warning.
function(holo_uses_std_regex target)
  if(HOLO_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
endfunction()

# holo_module(NAME SOURCES ... DEPS ...): a module library holo_NAME with its public
# headers under NAME/include/holo/NAME and an alias holo::NAME.
# A module whose sources have not landed yet is an INTERFACE library of its headers.
function(holo_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  if(NOT ARG_SOURCES)
    add_library(holo_${name} INTERFACE)
    add_library(holo::${name} ALIAS holo_${name})
    set_property(GLOBAL APPEND PROPERTY HOLO_MODULE_LIBRARIES holo_${name})
    target_include_directories(holo_${name} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_link_libraries(holo_${name} INTERFACE ${ARG_DEPS})
    return()
  endif()
  add_library(holo_${name} STATIC ${ARG_SOURCES})
  add_library(holo::${name} ALIAS holo_${name})
  set_property(GLOBAL APPEND PROPERTY HOLO_MODULE_LIBRARIES holo_${name})
  target_include_directories(holo_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(holo_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  holo_set_warnings(holo_${name})
endfunction()

# holo_test(NAME SOURCES ... DEPS ... [RESOURCE_LOCK both_cores]): one GoogleTest executable
# registered with ctest. Tests run from the source root so they can find ../shared/data as the
# README says. RESOURCE_LOCK both_cores marks tests that keep both cores busy for long (whole
# pipelines, soaks, evaluations): ctest runs no two of them at the same time.
function(holo_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT;RESOURCE_LOCK" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main GTest::gmock)
  if(HOLO_SANITIZE STREQUAL "thread")
    target_sources(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support/tsan_one_tbb_thread.cpp)
    target_link_libraries(${name} PRIVATE TBB::tbb)
  endif()
  holo_set_warnings(${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  holo_test_timeout(ARG_TIMEOUT ${ARG_TIMEOUT})
  set(properties TIMEOUT ${ARG_TIMEOUT})
  if(ARG_LABELS)
    list(APPEND properties LABELS "${ARG_LABELS}")
  endif()
  if(ARG_RESOURCE_LOCK)
    list(APPEND properties RESOURCE_LOCK ${ARG_RESOURCE_LOCK})
  endif()
  gtest_discover_tests(${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                       PROPERTIES ${properties}
                       DISCOVERY_TIMEOUT 60)
endfunction()

# holo_benchmark(NAME SOURCES ... DEPS ...): a Google Benchmark executable. Its figures are read
# from a run by hand (medians and ratios); ctest runs every benchmark once for a moment
# (NAME_runs), so one that crashes or throws fails CI. No timing is checked there.
function(holo_benchmark name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark benchmark::benchmark_main)
  holo_set_warnings(${name})
  add_test(NAME ${name}_runs COMMAND ${name} --benchmark_min_time=0.001 WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  # A benchmark that calls SkipWithError still exits 0; its report says ERROR OCCURRED.
  holo_test_timeout(timeout 600)
  set_tests_properties(${name}_runs PROPERTIES LABELS benchmark TIMEOUT ${timeout} FAIL_REGULAR_EXPRESSION "ERROR OCCURRED")
endfunction()
