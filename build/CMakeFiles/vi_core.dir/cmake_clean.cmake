file(REMOVE_RECURSE
  "CMakeFiles/vi_core.dir/src/vi_contact.c.o"
  "CMakeFiles/vi_core.dir/src/vi_contact.c.o.d"
  "CMakeFiles/vi_core.dir/src/vi_model.c.o"
  "CMakeFiles/vi_core.dir/src/vi_model.c.o.d"
  "CMakeFiles/vi_core.dir/src/vi_sim.c.o"
  "CMakeFiles/vi_core.dir/src/vi_sim.c.o.d"
  "CMakeFiles/vi_core.dir/src/vi_solver.c.o"
  "CMakeFiles/vi_core.dir/src/vi_solver.c.o.d"
  "CMakeFiles/vi_core.dir/src/vi_variables.c.o"
  "CMakeFiles/vi_core.dir/src/vi_variables.c.o.d"
  "libvi_core.a"
  "libvi_core.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/vi_core.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
