file(REMOVE_RECURSE
  "CMakeFiles/test_contact.dir/tests/test_contact.c.o"
  "CMakeFiles/test_contact.dir/tests/test_contact.c.o.d"
  "test_contact"
  "test_contact.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/test_contact.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
