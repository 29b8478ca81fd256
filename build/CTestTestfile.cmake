# CMake generated Testfile for 
# Source directory: /work/main
# Build directory: /work/main/build
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
add_test(contact "/work/main/build/test_contact" "--verbose")
set_tests_properties(contact PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;78;add_test;/work/main/CMakeLists.txt;0;")
add_test(model "/work/main/build/test_model" "--verbose")
set_tests_properties(model PROPERTIES  _BACKTRACE_TRIPLES "/work/main/CMakeLists.txt;78;add_test;/work/main/CMakeLists.txt;0;")
