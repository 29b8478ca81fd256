# The libFuzzer harness of the FMU (tests/fuzz/README.md), included at the end of the top-level
# CMakeLists.txt. Two roles:
#
# - In a normal build (any compiler): with VI_FUZZ (default ON, except under VI_SANITIZE), find clang
#   with libFuzzer and build the whole project again with it into <build>/fuzz (an external
#   project, configured with VI_FUZZ_HARNESS=ON), and add the ctest test `fuzz_<FMU>`: the harness on the
#   seed corpus tests/fuzz/corpus for VI_FUZZ_SECONDS (60) seconds. Without clang's libFuzzer the
#   configuration fails when VI_REQUIRE_TESTS is on (tools/setup.sh installs clang and
#   libclang-rt-14-dev), else it warns and the test is left out.
# - In that inner build (VI_FUZZ_HARNESS=ON, C compiler clang): every target is compiled with
#   -fsanitize=fuzzer-no-link,address,undefined, and fuzz_<FMU> links the harness with the FMU's own
#   sources (those of its shared library target and of its model objects), so that the harness calls
#   the fmi2* functions directly and the sources stay those of the FMU.
option(VI_FUZZ_HARNESS "Internal: this is the clang build of the libFuzzer harness" OFF)
set(VI_FUZZ_DIR ${CMAKE_CURRENT_LIST_DIR})
# The FMU binaries the harness is built for, fuzz_<target>, and the call kinds each offers.
# fuzz_VibroImpact links the FMI 2.0 and the FMI 3.0 face (VI_FUZZ_ALSO_VibroImpact: the union of
# both targets' sources, the core once; the fmi3* and fmi2* names do not clash), so that one input
# drives instances of both versions and shares serialized FMU states between them;
# fuzz_VibroImpact_fmi3 is the FMI 3.0 binary alone.
set(VI_FUZZ_TARGETS VibroImpact VibroImpact_fmi3)
set(VI_FUZZ_CALLS_VibroImpact calls_fmi2.c calls_fmi2me.c calls_fmi3.c)
set(VI_FUZZ_ALSO_VibroImpact VibroImpact_fmi3)
set(VI_FUZZ_CALLS_VibroImpact_fmi3 calls_fmi3.c)
set(VI_FUZZ_SECONDS_VibroImpact_fmi3 30) # the FMI 3.0 face is thin over the same core

if(VI_FUZZ_HARNESS)
  find_package(Threads REQUIRED)
  foreach(target ${VI_FUZZ_TARGETS})
    if(NOT TARGET ${target})
      continue()
    endif()
    set(calls "")
    foreach(f ${VI_FUZZ_CALLS_${target}})
      list(APPEND calls ${VI_FUZZ_DIR}/${f})
    endforeach()
    # the FMU binary's own sources, definitions and model objects (and those of the targets it also
    # links, each source once), with the harness
    set(sources $<TARGET_PROPERTY:${target},SOURCES>)
    set(definitions $<TARGET_PROPERTY:${target},COMPILE_DEFINITIONS>)
    foreach(also ${VI_FUZZ_ALSO_${target}})
      if(TARGET ${also})
        string(APPEND sources ";$<TARGET_PROPERTY:${also},SOURCES>")
        string(APPEND definitions ";$<TARGET_PROPERTY:${also},COMPILE_DEFINITIONS>")
      endif()
    endforeach()
    add_executable(fuzz_${target} ${VI_FUZZ_DIR}/fuzz_main.c ${VI_FUZZ_DIR}/order.c ${VI_FUZZ_DIR}/energy.c ${calls} "$<REMOVE_DUPLICATES:${sources}>")
    target_include_directories(fuzz_${target} PRIVATE ${FMI2_HEADERS_DIR} ${VI_FUZZ_DIR} ${VI_INCLUDE_DIRS})
    target_compile_definitions(fuzz_${target} PRIVATE "$<REMOVE_DUPLICATES:${definitions}>")
    string(REGEX REPLACE "_fmi3$" "" fmu ${target}) # both binaries of an FMU link its model objects
    target_link_libraries(fuzz_${target} PRIVATE ${fmu}_model Threads::Threads m)
    target_compile_options(fuzz_${target} PRIVATE ${VI_WARNINGS})
    target_link_options(fuzz_${target} PRIVATE -fsanitize=fuzzer,address,undefined)
  endforeach()
  return()
endif()

if(VI_SANITIZE)
  set(fuzz_default OFF) # the clang build runs once, from the normal build tree
else()
  set(fuzz_default ON)
endif()
option(VI_FUZZ "Build the libFuzzer harness with clang and run it in ctest (test 'fuzz')" ${fuzz_default})
set(VI_FUZZ_SECONDS 60 CACHE STRING "Seconds the ctest test 'fuzz' runs the harness")
if(NOT VI_FUZZ)
  return()
endif()

# clang that links a libFuzzer target with ASan and UBSan
find_program(VI_CLANG NAMES clang clang-16 clang-15 clang-14)
set(fuzz_ok FALSE)
if(VI_CLANG)
  set(probe_dir ${CMAKE_BINARY_DIR}/fuzz-probe)
  file(WRITE ${probe_dir}/probe.c
       "#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n")
  execute_process(COMMAND ${VI_CLANG} -fsanitize=fuzzer,address,undefined probe.c -o probe
                  WORKING_DIRECTORY ${probe_dir} RESULT_VARIABLE probe_rc OUTPUT_QUIET ERROR_VARIABLE probe_err)
  if(probe_rc EQUAL 0)
    set(fuzz_ok TRUE)
  endif()
endif()
if(NOT fuzz_ok)
  set(why "clang with libFuzzer not found (VI_CLANG=${VI_CLANG}): install clang and libclang-rt-14-dev (tools/setup.sh does), or configure with -DVI_FUZZ=OFF")
  if(VI_REQUIRE_TESTS)
    message(FATAL_ERROR "${why}")
  endif()
  message(WARNING "${why}; the fuzz test is left out")
  return()
endif()
message(STATUS "libFuzzer harness: ${VI_CLANG} -> ${CMAKE_BINARY_DIR}/fuzz")

include(ExternalProject)
set(fuzz_targets "")
foreach(target ${VI_FUZZ_TARGETS})
  list(APPEND fuzz_targets --target fuzz_${target})
endforeach()
ExternalProject_Add(vi_fuzz_harness
  SOURCE_DIR ${CMAKE_SOURCE_DIR}
  BINARY_DIR ${CMAKE_BINARY_DIR}/fuzz
  CMAKE_ARGS -DCMAKE_C_COMPILER=${VI_CLANG} -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVI_FUZZ_HARNESS=ON -DVI_FUZZ=OFF
             -DPython3_EXECUTABLE=${Python3_EXECUTABLE}
             # SUNDIALS' package asks for OpenMP: clang without its own runtime uses the one gcc found
             -DOpenMP_C_FLAGS=-fopenmp=libgomp "-DOpenMP_C_LIB_NAMES=${OpenMP_C_LIB_NAMES}"
             -DOpenMP_gomp_LIBRARY=${OpenMP_gomp_LIBRARY} -DOpenMP_pthread_LIBRARY=${OpenMP_pthread_LIBRARY}
             "-DCMAKE_C_FLAGS=-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
  BUILD_COMMAND ${CMAKE_COMMAND} --build <BINARY_DIR> ${fuzz_targets}
  BUILD_ALWAYS ON
  INSTALL_COMMAND ""
  EXCLUDE_FROM_ALL OFF)

# The ctest runs: the seed corpus (read only) plus a scratch corpus in the build tree, for
# VI_FUZZ_SECONDS (or the target's own VI_FUZZ_SECONDS_<target>), with the mutation seed
# VI_FUZZ_SEED, so that every machine tries the same inputs first (a faster one goes further);
# findings go to <build>/fuzz/findings/. tools/fuzz.sh runs longer campaigns with fresh seeds.
set(VI_FUZZ_SEED 1 CACHE STRING "libFuzzer's -seed for the ctest fuzz runs (0: a fresh one each run)")
foreach(target ${VI_FUZZ_TARGETS})
  set(seconds ${VI_FUZZ_SECONDS})
  if(DEFINED VI_FUZZ_SECONDS_${target})
    set(seconds ${VI_FUZZ_SECONDS_${target}})
  endif()
  set(work ${CMAKE_BINARY_DIR}/fuzz/corpus-${target})
  file(MAKE_DIRECTORY ${work} ${CMAKE_BINARY_DIR}/fuzz/findings)
  add_test(NAME fuzz_${target} COMMAND ${CMAKE_BINARY_DIR}/fuzz/fuzz_${target} -seed=${VI_FUZZ_SEED} -max_total_time=${seconds} -timeout=600
           -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix=${CMAKE_BINARY_DIR}/fuzz/findings/
           ${work} ${VI_FUZZ_DIR}/corpus/${target})
  math(EXPR fuzz_timeout "${seconds} + 600")
  set_tests_properties(fuzz_${target} PROPERTIES TIMEOUT ${fuzz_timeout} LABELS fuzz
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1:abort_on_error=1;UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1")
endforeach()
