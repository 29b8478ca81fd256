file(REMOVE_RECURSE
  "CMakeFiles/vi_dump_variables.dir/tests/dump_variables.c.o"
  "CMakeFiles/vi_dump_variables.dir/tests/dump_variables.c.o.d"
  "vi_dump_variables"
  "vi_dump_variables.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/vi_dump_variables.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
