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
set(VI_FUZZ_FMUS VibroImpact) # the FMUs the harness is built for: fuzz_<name>

if(VI_FUZZ_HARNESS)
  find_package(Threads REQUIRED)
  foreach(fmu ${VI_FUZZ_FMUS})
    add_executable(fuzz_${fmu} ${VI_FUZZ_DIR}/fuzz_main.c ${VI_FUZZ_DIR}/calls_fmi2.c ${VI_FUZZ_DIR}/calls_fmi2me.c
                   $<TARGET_PROPERTY:${fmu},SOURCES>)
    target_include_directories(fuzz_${fmu} PRIVATE ${FMI2_HEADERS_DIR} ${VI_FUZZ_DIR} ${CMAKE_SOURCE_DIR}/include)
    target_link_libraries(fuzz_${fmu} PRIVATE ${fmu}_model Threads::Threads m)
    target_compile_options(fuzz_${fmu} PRIVATE ${VI_WARNINGS})
    target_link_options(fuzz_${fmu} PRIVATE -fsanitize=fuzzer,address,undefined)
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
foreach(fmu ${VI_FUZZ_FMUS})
  list(APPEND fuzz_targets --target fuzz_${fmu})
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

# The ctest run: the seed corpus (read only) plus a scratch corpus in the build tree, for
# VI_FUZZ_SECONDS; findings go to <build>/fuzz/findings/. tools/fuzz.sh runs longer campaigns.
foreach(fmu ${VI_FUZZ_FMUS})
  set(work ${CMAKE_BINARY_DIR}/fuzz/corpus-${fmu})
  file(MAKE_DIRECTORY ${work} ${CMAKE_BINARY_DIR}/fuzz/findings)
  add_test(NAME fuzz_${fmu} COMMAND ${CMAKE_BINARY_DIR}/fuzz/fuzz_${fmu} -max_total_time=${VI_FUZZ_SECONDS} -timeout=600
           -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix=${CMAKE_BINARY_DIR}/fuzz/findings/
           ${work} ${VI_FUZZ_DIR}/corpus/${fmu})
  math(EXPR fuzz_timeout "${VI_FUZZ_SECONDS} + 600")
  set_tests_properties(fuzz_${fmu} PROPERTIES TIMEOUT ${fuzz_timeout} LABELS fuzz
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=1:abort_on_error=1;UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1")
endforeach()
