# Sanitizer and fuzzing builds (scripts/test --sanitize, scripts/fuzz), each in a build folder of
# its own. HOLO_SANITIZE instruments every target of the project: "address,undefined" or
# "thread". HOLO_FUZZ adds libFuzzer's coverage instrumentation and the targets of tests/fuzz
# (clang only).
set(HOLO_SANITIZE "" CACHE STRING "Sanitizers for every target: address,undefined or thread")
option(HOLO_FUZZ "Build the libFuzzer targets of tests/fuzz (clang)" OFF)

if(HOLO_SANITIZE)
  # Every report is a failure: recovering would let a test pass with undefined behaviour in it.
  add_compile_options(-fsanitize=${HOLO_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer -g)
  add_link_options(-fsanitize=${HOLO_SANITIZE})
endif()

# Instrumented programs run several times slower (ThreadSanitizer the most), so every test's time
# limit stretches by this factor: a limit is there to catch a hang, not to judge speed.
if(HOLO_SANITIZE STREQUAL "thread")
  set(HOLO_TEST_TIMEOUT_SCALE 8)
elseif(HOLO_SANITIZE)
  set(HOLO_TEST_TIMEOUT_SCALE 4)
else()
  set(HOLO_TEST_TIMEOUT_SCALE 1)
endif()

# holo_test_timeout(VAR SECONDS): SECONDS stretched for this build, into VAR.
function(holo_test_timeout var seconds)
  math(EXPR scaled "${seconds} * ${HOLO_TEST_TIMEOUT_SCALE}")
  set(${var} ${scaled} PARENT_SCOPE)
endfunction()

if(HOLO_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "HOLO_FUZZ needs clang (libFuzzer): configure with CC=clang CXX=clang++")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
