# Coverage builds for tools/mutate.py (its map of which test executes which line of src/): configure
# with -DVI_COVERAGE=ON. Everything is compiled with --coverage at -O0 (exact line attribution), and
# each FMU binary gets vi_coverage_flush() (tests/coverage_flush.c), which writes its counters and
# resets them, for runners that keep the FMU loaded between tests.
option(VI_COVERAGE "Build for coverage measurement (tools/mutate.py)" OFF)
if(VI_COVERAGE)
  foreach(fmu VibroImpact LayerTest Track Vehicle VibroImpact_fmi3 LayerTest_fmi3 Track_fmi3 Vehicle_fmi3)
    if(TARGET ${fmu})
      target_sources(${fmu} PRIVATE ${CMAKE_CURRENT_LIST_DIR}/coverage_flush.c)
    endif()
  endforeach()
endif()
