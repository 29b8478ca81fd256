# The platform the FMU binaries are built for (the build machine, or a cross target given by a
# toolchain file in this folder: toolchain-x86_64-windows.cmake, toolchain-aarch64-linux.cmake).
#
#   VI_FMI2_PLATFORM  the FMI 2.0 binaries folder: linux64, win64, darwin64; empty where FMI 2.0 names
#                     no platform (aarch64 Linux): vi_add_fmu() then builds the binary but packs no FMU
#   VI_FMI3_PLATFORM  the FMI 3.0 platform tuple: x86_64-linux, x86_64-windows, aarch64-linux, ...
#
# Windows (mingw-w64): printf and friends follow C99 (mingw's own stdio, linked statically: %zu,
# two-digit exponents) and libgcc is linked statically, so that a DLL or program imports only
# Windows system DLLs (KERNEL32.dll and the C runtime msvcrt.dll).

include_guard(GLOBAL)

set(_vi_arch ${CMAKE_SYSTEM_PROCESSOR})
string(TOLOWER "${_vi_arch}" _vi_arch)
if(_vi_arch MATCHES "^(x86_64|amd64|x64)$")
  set(_vi_arch x86_64)
elseif(_vi_arch MATCHES "^(aarch64|arm64)$")
  set(_vi_arch aarch64)
endif()

if(WIN32)
  set(_vi_os windows)
elseif(APPLE)
  set(_vi_os darwin)
else()
  string(TOLOWER "${CMAKE_SYSTEM_NAME}" _vi_os)
endif()
set(VI_FMI3_PLATFORM ${_vi_arch}-${_vi_os})

set(VI_FMI2_PLATFORM "")
if(CMAKE_SIZEOF_VOID_P EQUAL 8 AND _vi_arch STREQUAL "x86_64")
  if(_vi_os STREQUAL "windows")
    set(VI_FMI2_PLATFORM win64)
  elseif(_vi_os STREQUAL "linux")
    set(VI_FMI2_PLATFORM linux64)
  elseif(_vi_os STREQUAL "darwin")
    set(VI_FMI2_PLATFORM darwin64)
  endif()
endif()
message(STATUS "FMU platform: FMI 2.0 '${VI_FMI2_PLATFORM}', FMI 3.0 '${VI_FMI3_PLATFORM}'")

if(MINGW)
  add_compile_definitions(__USE_MINGW_ANSI_STDIO=1)
  add_link_options(-static-libgcc -Wl,--no-insert-timestamp) # no link time in the DLL: the same bytes every build
endif()
