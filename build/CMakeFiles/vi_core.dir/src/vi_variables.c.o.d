CMakeFiles/vi_core.dir/src/vi_variables.c.o: \
 /work/main/src/vi_variables.c /usr/include/stdc-predef.h \
 /work/main/include/vi_variables.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/stddef.h
