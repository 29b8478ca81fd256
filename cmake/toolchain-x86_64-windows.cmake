# CMake toolchain file: 64-bit Windows with Debian's mingw-w64 cross compiler (gcc-mingw-w64-x86-64).
# Used by tools/release.sh for SUNDIALS and for the FMUs: cmake -DCMAKE_TOOLCHAIN_FILE=<this file>.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(VI_CROSS_TRIPLE x86_64-w64-mingw32)

# The win32 thread model: its runtime needs no libwinpthread DLL.
find_program(CMAKE_C_COMPILER NAMES ${VI_CROSS_TRIPLE}-gcc-win32 ${VI_CROSS_TRIPLE}-gcc REQUIRED)
find_program(CMAKE_RC_COMPILER NAMES ${VI_CROSS_TRIPLE}-windres)

set(CMAKE_FIND_ROOT_PATH /usr/${VI_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Programs built for this target run here under wine64 (ctest, try_run).
find_program(VI_WINE NAMES wine64 wine PATHS /usr/lib/wine NO_DEFAULT_PATH)
find_program(VI_WINE NAMES wine64 wine)
if(VI_WINE)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${VI_WINE})
endif()
