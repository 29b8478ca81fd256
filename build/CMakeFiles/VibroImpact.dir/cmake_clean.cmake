file(REMOVE_RECURSE
  "CMakeFiles/VibroImpact.dir/src/vi_fmi2.c.o"
  "CMakeFiles/VibroImpact.dir/src/vi_fmi2.c.o.d"
  "VibroImpact.pdb"
  "VibroImpact.so"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/VibroImpact.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
