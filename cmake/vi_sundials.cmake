# SUNDIALS for the solver (src/solvers/vi_solver.c, src/solvers/vi_sundials.h): 6.4 or 7.x, linked statically
# (the FMU binaries export their fmi* functions only: cmake/vi_fmu.cmake).
#
# The SUNDIALS CMake package CMake finds (Debian's libsundials-dev: 6.4.1), or the one -DSUNDIALS_DIR=
# names (<prefix>/lib/cmake/sundials, or lib64/), gives the integrator: CVODE where that SUNDIALS has
# it, else CVODES, which holds CVODE's whole API (SUNDIALS 7.9 of the sundials4py wheel has CVODES
# only). Defines:
#   vi_cvode               an interface library: the static integrator library (with SUNDIALS' core),
#                          VI_SUNDIALS_CVODES=1 when it is CVODES
#   VI_SUNDIALS_CARRIED    what the binaries carry, e.g. "SUNDIALS 6.4.1 CVODE"
#   VI_FMU_GENERATION_TOOL the generationTool of the model descriptions of the FMUs that carry it
#                          (vi_add_fmu's GENERATION_TOOL): "VibroImpact <version> with SUNDIALS 6.4.1
#                          CVODE linked statically"
#   VI_SUNDIALS_LICENSE    the copyright and licence of that SUNDIALS, which its BSD-3-Clause licence
#                          asks binaries to carry in their documentation (documentation/licenses/
#                          SUNDIALS.txt of each FMU): Debian's copyright file of libsundials-dev for
#                          Debian's SUNDIALS, else its LICENSE and NOTICE (include/sundials/ of its
#                          prefix), joined in the build directory; -DVI_SUNDIALS_LICENSE=<file> gives
#                          another
find_package(SUNDIALS CONFIG)
if(NOT SUNDIALS_FOUND)
  message(FATAL_ERROR "SUNDIALS not found: install libsundials-dev (tools/setup.sh), or give "
                      "-DSUNDIALS_DIR=<the folder of its SUNDIALSConfig.cmake: lib/cmake/sundials or lib64/cmake/sundials>")
endif()
if(SUNDIALS_VERSION VERSION_LESS 6.4 OR NOT SUNDIALS_VERSION VERSION_LESS 8)
  message(FATAL_ERROR "SUNDIALS ${SUNDIALS_VERSION} (${SUNDIALS_DIR}): the solver is written for SUNDIALS 6.4 to 7.x")
endif()
if(TARGET SUNDIALS::cvode_static)
  set(vi_integrator cvode)
elseif(TARGET SUNDIALS::cvodes_static)
  set(vi_integrator cvodes)
else()
  message(FATAL_ERROR "SUNDIALS ${SUNDIALS_VERSION} (${SUNDIALS_DIR}) has no static CVODE or CVODES library")
endif()
string(TOUPPER ${vi_integrator} vi_integrator_name)
set(VI_SUNDIALS_CARRIED "SUNDIALS ${SUNDIALS_VERSION} ${vi_integrator_name}")
message(STATUS "${VI_SUNDIALS_CARRIED} (static): ${SUNDIALS_DIR}")
set(VI_FMU_GENERATION_TOOL "VibroImpact ${PROJECT_VERSION} with ${VI_SUNDIALS_CARRIED} linked statically")

add_library(vi_cvode INTERFACE)
target_link_libraries(vi_cvode INTERFACE SUNDIALS::${vi_integrator}_static)
if(vi_integrator STREQUAL "cvodes")
  target_compile_definitions(vi_cvode INTERFACE VI_SUNDIALS_CVODES=1)
endif()

# the licence: given, Debian's copyright file, or LICENSE and NOTICE beside the headers
set(VI_SUNDIALS_LICENSE "" CACHE FILEPATH
    "The copyright and licence of the SUNDIALS the build links (empty: found beside it, cmake/vi_sundials.cmake)")
if(NOT VI_SUNDIALS_LICENSE)
  get_target_property(vi_sundials_include SUNDIALS::${vi_integrator}_static INTERFACE_INCLUDE_DIRECTORIES)
  list(GET vi_sundials_include 0 vi_sundials_include)
  set(vi_debian_copyright /usr/share/doc/libsundials-dev/copyright)
  if(vi_sundials_include STREQUAL "/usr/include" AND EXISTS ${vi_debian_copyright})
    set(VI_SUNDIALS_LICENSE ${vi_debian_copyright})
  elseif(EXISTS ${vi_sundials_include}/sundials/LICENSE)
    file(READ ${vi_sundials_include}/sundials/LICENSE vi_text)
    if(EXISTS ${vi_sundials_include}/sundials/NOTICE)
      file(READ ${vi_sundials_include}/sundials/NOTICE vi_notice)
      string(APPEND vi_text "\n${vi_notice}")
    endif()
    set(VI_SUNDIALS_LICENSE ${CMAKE_BINARY_DIR}/SUNDIALS-LICENSE.txt)
    set(vi_old "")
    if(EXISTS ${VI_SUNDIALS_LICENSE})
      file(READ ${VI_SUNDIALS_LICENSE} vi_old)
    endif()
    if(NOT vi_old STREQUAL vi_text) # written again only when it changes (the FMUs depend on it)
      file(WRITE ${VI_SUNDIALS_LICENSE} "${vi_text}")
    endif()
  else()
    message(FATAL_ERROR "The licence of SUNDIALS (${SUNDIALS_DIR}) not found: neither Debian's "
                        "${vi_debian_copyright} nor ${vi_sundials_include}/sundials/LICENSE; give "
                        "-DVI_SUNDIALS_LICENSE=<the LICENSE file of the SUNDIALS source the build links>")
  endif()
elseif(NOT EXISTS "${VI_SUNDIALS_LICENSE}")
  message(FATAL_ERROR "VI_SUNDIALS_LICENSE=${VI_SUNDIALS_LICENSE}: no such file")
endif()
