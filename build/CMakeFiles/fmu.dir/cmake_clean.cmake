file(REMOVE_RECURSE
  "CMakeFiles/fmu"
  "VibroImpact.fmu"
)

# Per-language clean rules from dependency scanning.
foreach(lang )
  include(CMakeFiles/fmu.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
