# CMake toolchain file: 64-bit ARM Linux with Debian's cross compiler (gcc-aarch64-linux-gnu and
# libc6-dev-arm64-cross). Used by tools/release.sh for SUNDIALS and for the FMU binaries:
# cmake -DCMAKE_TOOLCHAIN_FILE=<this file>.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(VI_CROSS_TRIPLE aarch64-linux-gnu)

find_program(CMAKE_C_COMPILER NAMES ${VI_CROSS_TRIPLE}-gcc REQUIRED)

set(CMAKE_FIND_ROOT_PATH /usr/${VI_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Programs built for this target run here under qemu-user (ctest, try_run, build steps), which finds
# the aarch64 C library through QEMU_LD_PREFIX (as -L would: no option-like word in the command).
find_program(VI_QEMU NAMES qemu-aarch64 qemu-aarch64-static)
find_program(VI_ENV env)
if(VI_QEMU AND VI_ENV)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${VI_ENV} QEMU_LD_PREFIX=/usr/${VI_CROSS_TRIPLE} ${VI_QEMU})
endif()
