# RETREAT_BUILD_FUZZERS: a separate Clang build tree whose every library is instrumented for
# libFuzzer with AddressSanitizer and UndefinedBehaviorSanitizer; tests/fuzz adds the fuzz
# targets and a short CTest run of each (label `fuzz`). docs/fuzzing.md.
if(NOT RETREAT_BUILD_FUZZERS)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang" OR NOT CMAKE_C_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "RETREAT_BUILD_FUZZERS=ON needs Clang (libFuzzer), not "
    "${CMAKE_CXX_COMPILER_ID}: configure with -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++")
endif()
# Instrument everything (coverage for the fuzzer, sanitizers for the bugs); only the fuzz
# targets link libFuzzer's main (tests/fuzz/CMakeLists.txt).
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all
  -fno-omit-frame-pointer)
add_link_options(-fsanitize=address,undefined)
enable_testing()
