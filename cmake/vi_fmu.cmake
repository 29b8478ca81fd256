# vi_add_fmu(<Name> SOURCES <model .c files...> XML <modelDescription.xml>
#            [FMI_VERSIONS <2 and/or 3> (default 2)]
#            [LIBRARIES <libraries...>] [INCLUDE_DIRS <dirs...> (the calling folder is one already)]
#            [RESOURCES <files...>] [OUTPUT_DIRECTORY <dir>]
#            [DOC_INTRO <README.md>] [DOCUMENTATION <pages.md...>] [DOCUMENTATION_FMI3 <pages.md...>]
#            [LICENSES <NAME=file>...] [ICON <png>])
#
# Builds Co-Simulation FMUs of one model on the generic layer (include/vi_fmu.h), one per FMI version,
# all from the same compiled model (<Name>_model):
#   FMI 2.0 (the XML given, hand-written and tested against the model's table, stamped with the release by
#   cmake/vi_fmu_stamp.py: version, generationDateAndTime, copyright, license):
#     <Name>               the shared library <Name>.so (.dll on Windows): the model + the layer
#                          (src/vi_fmi_core.c and the FMI 2.0 face src/vi_fmi2.c), exporting the fmi2*
#                          functions only (static libraries linked in stay hidden); it must match
#                          modelIdentifier="<Name>" in the XML
#     <Name>_fmu (ALL)     packs <OUTPUT_DIRECTORY>/<Name>.fmu (default: the top build directory):
#                          modelDescription.xml, binaries/<VI_FMI2_PLATFORM>/<Name>.so, resources/,
#                          documentation/_main.html, model.png (ICON) (no FMU where FMI 2.0 names no
#                          platform: aarch64 Linux)
#   FMI 3.0 (the model description generated from the table and the stamped FMI 2.0 XML by
#   cmake/vi_fmi3_description.py):
#     <Name>_fmi3          the shared library <OUTPUT_DIRECTORY>/fmi3/<Name>.so: the model + the layer
#                          (src/vi_fmi_core.c and the FMI 3.0 face src/vi_fmi3.c), exporting the fmi3*
#                          functions only
#     <Name>_fmi3_fmu (ALL) packs <OUTPUT_DIRECTORY>/fmi3/<Name>.fmu: modelDescription.xml,
#                          binaries/<VI_FMI3_PLATFORM>/<Name>.so, resources/, documentation/index.html,
#                          terminalsAndIcons/icon.png (ICON)
#   <Name>_dump_variables  prints the model's variable table (tests/dump_variables.c), for the test that
#                          compares the table with the XML and for the FMI 3.0 description
# The model's sources must define `const vi_fmu_model vi_fmu_this_model` and its table (vi_table.h).
#
# The platform comes from cmake/vi_platform.cmake (the build machine or a cross toolchain file).
# VI_FMU_MERGE_BINARIES (cache, a list of build directories of the same sources for other platforms,
# tools/release.sh): each FMU packed here also holds the binaries/ of the FMU at the same place in each
# of those builds (where there is one), whose modelDescription.xml must equal this one.
#
# ---- documentation, licences, icon, version (cmake/vi_fmu_doc.py, cmake/vi_fmu_stamp.py) ----------------
# documentation/ of every FMU: the page FMI names as the entry point (_main.html for 2.0, index.html for
# 3.0) made from DOC_INTRO (its part before the first '## '), the DOCUMENTATION pages (and for FMI 3.0 the
# DOCUMENTATION_FMI3 ones), the variable table and the licences, with the images it shows; licenses/ with
# license.txt (the repository's LICENSE) and NAME.txt for each LICENSES entry NAME=file (the copyright and
# licence of third-party code the binaries carry, copied at build time). ICON is the model's icon.
# The version is the CMake project's (PROJECT_VERSION); the generation date SOURCE_DATE_EPOCH's when it
# is set (at build time, else at configure time), else the time the description is stamped.
# -----------------------------------------------------------------------------------------------------------
set(VI_FMU_ROOT ${CMAKE_CURRENT_LIST_DIR}/..)
include(${CMAKE_CURRENT_LIST_DIR}/vi_platform.cmake)
set(VI_FMU_MERGE_BINARIES "" CACHE STRING
    "Build directories of other platforms whose FMU binaries the FMUs packed here also hold")
# Value references of every FMI 3.0 FMU that are no row of a table: the independent variable `time`,
# and der(<input>) of the Real input in row r at VI_FMI3_DERIVATIVE_VR_BASE + r.
set(VI_FMI3_TIME_VR 2147483647)
set(VI_FMI3_DERIVATIVE_VR_BASE 1073741824)
# and, in Model Exchange, event indicator i at VI_FMI3_INDICATOR_VR_BASE + i
set(VI_FMI3_INDICATOR_VR_BASE 1610612736)

# ---- the release stamp: version and SOURCE_DATE_EPOCH of this configuration ---------------------------------
# A file that changes when either changes, so that the stamped model descriptions are made again.
set(VI_FMU_RELEASE_STAMP ${CMAKE_BINARY_DIR}/vi_release_stamp.txt)
set(stamp_text "version=${PROJECT_VERSION}\nSOURCE_DATE_EPOCH=$ENV{SOURCE_DATE_EPOCH}\n")
if(EXISTS ${VI_FMU_RELEASE_STAMP})
  file(READ ${VI_FMU_RELEASE_STAMP} stamp_old)
endif()
if(NOT stamp_old STREQUAL stamp_text)
  file(WRITE ${VI_FMU_RELEASE_STAMP} "${stamp_text}")
endif()
# ---- end of the release stamp -----------------------------------------------------------------------------

function(vi_add_fmu name)
  cmake_parse_arguments(ARG "" "XML;OUTPUT_DIRECTORY;DOC_INTRO;ICON"
                        "SOURCES;LIBRARIES;INCLUDE_DIRS;RESOURCES;FMI_VERSIONS;DOCUMENTATION;DOCUMENTATION_FMI3;LICENSES"
                        ${ARGN})
  if(NOT ARG_SOURCES OR NOT ARG_XML)
    message(FATAL_ERROR "vi_add_fmu(${name}): SOURCES and XML are required")
  endif()
  if(NOT ARG_OUTPUT_DIRECTORY)
    set(ARG_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR})
  endif()
  if(NOT ARG_FMI_VERSIONS)
    set(ARG_FMI_VERSIONS 2)
  endif()
  get_filename_component(xml_written ${ARG_XML} ABSOLUTE)

  # The model without the FMI layer: shared by the FMU binaries and the table dump.
  add_library(${name}_model OBJECT ${ARG_SOURCES})
  target_include_directories(${name}_model PUBLIC ${VI_FMU_ROOT}/include ${CMAKE_CURRENT_SOURCE_DIR} ${ARG_INCLUDE_DIRS})
  target_compile_options(${name}_model PRIVATE ${VI_WARNINGS})
  target_link_libraries(${name}_model PUBLIC ${ARG_LIBRARIES} m)
  set_target_properties(${name}_model PROPERTIES C_VISIBILITY_PRESET hidden POSITION_INDEPENDENT_CODE ON)

  add_executable(${name}_dump_variables ${VI_FMU_ROOT}/tests/dump_variables.c)
  target_compile_options(${name}_dump_variables PRIVATE ${VI_WARNINGS})
  target_link_libraries(${name}_dump_variables PRIVATE ${name}_model)
  set_target_properties(${name}_dump_variables PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})

  # ---- version, documentation, licences, icon ----------------------------------------------------------
  # The hand-written FMI 2.0 description stamped with the release; the FMI 3.0 one is generated from it.
  set(xml ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmi2/modelDescription.xml)
  set(stamper ${VI_FMU_ROOT}/cmake/vi_fmu_stamp.py)
  add_custom_command(OUTPUT ${xml}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmi2
    COMMAND ${Python3_EXECUTABLE} ${stamper} --xml ${xml_written} --version ${PROJECT_VERSION}
            --source-date-epoch=$ENV{SOURCE_DATE_EPOCH} --license ${VI_FMU_ROOT}/LICENSE --out ${xml}
    DEPENDS ${stamper} ${xml_written} ${VI_FMU_ROOT}/LICENSE ${VI_FMU_RELEASE_STAMP}
    COMMENT "Stamping the FMI 2.0 modelDescription.xml of ${name} with version ${PROJECT_VERSION}")
  add_custom_target(${name}_stamp DEPENDS ${xml}) # one rule for the file the FMUs of both versions read
  set(doc_args --license ${VI_FMU_ROOT}/LICENSE)
  set(doc_inputs ${VI_FMU_ROOT}/cmake/vi_fmu_doc.py ${VI_FMU_ROOT}/cmake/vi_fmi3_description.py ${VI_FMU_ROOT}/LICENSE)
  foreach(notice ${ARG_LICENSES})
    string(REGEX REPLACE "^[^=]*=" "" notice_file "${notice}")
    list(APPEND doc_args --notice ${notice})
    list(APPEND doc_inputs ${notice_file})
  endforeach()
  # the Markdown pages: doc_DOC_INTRO, doc_DOCUMENTATION, doc_DOCUMENTATION_FMI3 (options of vi_fmu_doc.py)
  foreach(kind DOC_INTRO DOCUMENTATION DOCUMENTATION_FMI3)
    set(doc_${kind} "")
    set(option --page)
    if(kind STREQUAL "DOC_INTRO")
      set(option --intro)
    endif()
    foreach(f ${ARG_${kind}})
      get_filename_component(f ${f} ABSOLUTE)
      list(APPEND doc_${kind} ${option} ${f})
      list(APPEND doc_inputs ${f})
    endforeach()
  endforeach()
  list(APPEND doc_args ${doc_DOC_INTRO})
  set(icon "")
  if(ARG_ICON)
    get_filename_component(icon ${ARG_ICON} ABSOLUTE)
  endif()
  # ---- end of version, documentation, licences, icon -----------------------------------------------------

  foreach(version ${ARG_FMI_VERSIONS})
    if(version STREQUAL "2")
      set(target ${name})
      set(face ${VI_FMU_ROOT}/src/vi_fmi2.c)
      set(platform ${VI_FMI2_PLATFORM})
      set(out_dir ${ARG_OUTPUT_DIRECTORY})
      set(version_xml ${xml})
      set(version_pages ${doc_DOCUMENTATION})
      set(defs "")
    elseif(version STREQUAL "3")
      set(target ${name}_fmi3)
      set(face ${VI_FMU_ROOT}/src/vi_fmi3.c)
      set(platform ${VI_FMI3_PLATFORM})
      set(out_dir ${ARG_OUTPUT_DIRECTORY}/fmi3)
      set(version_xml ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmi3/modelDescription.xml)
      set(defs VI_FMI3_TIME_VR=${VI_FMI3_TIME_VR}u VI_FMI3_DERIVATIVE_VR_BASE=${VI_FMI3_DERIVATIVE_VR_BASE}u
               VI_FMI3_INDICATOR_VR_BASE=${VI_FMI3_INDICATOR_VR_BASE}u)
      set(generator ${VI_FMU_ROOT}/cmake/vi_fmi3_description.py)
      set(version_pages ${doc_DOCUMENTATION} ${doc_DOCUMENTATION_FMI3})
      add_custom_command(OUTPUT ${version_xml}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmi3
        COMMAND ${Python3_EXECUTABLE} ${generator} --fmi2 ${xml} --time-vr ${VI_FMI3_TIME_VR}
                --derivative-vr-base ${VI_FMI3_DERIVATIVE_VR_BASE} --indicator-vr-base ${VI_FMI3_INDICATOR_VR_BASE}
                --out ${version_xml}
                --dump ${CMAKE_CROSSCOMPILING_EMULATOR} $<TARGET_FILE:${name}_dump_variables>
        DEPENDS ${generator} ${xml} ${name}_dump_variables
        COMMENT "Generating the FMI 3.0 modelDescription.xml of ${name}")
    else()
      message(FATAL_ERROR "vi_add_fmu(${name}): FMI_VERSIONS ${version}: use 2 and/or 3")
    endif()

    add_library(${target} SHARED ${face} ${VI_FMU_ROOT}/src/vi_fmi_core.c)
    target_include_directories(${target} PRIVATE ${FMI2_HEADERS_DIR} ${VI_FMU_ROOT}/include)
    target_compile_definitions(${target} PRIVATE ${defs})
    target_compile_options(${target} PRIVATE ${VI_WARNINGS})
    target_link_libraries(${target} PRIVATE ${name}_model) # an object library: its objects go in
    target_link_options(${target} PRIVATE -Wl,--exclude-libs,ALL -Wl,--no-undefined) # ELF and PE (mingw-w64)
    set_target_properties(${target} PROPERTIES PREFIX "" OUTPUT_NAME ${name} C_VISIBILITY_PRESET hidden
                                               LIBRARY_OUTPUT_DIRECTORY ${out_dir}
                                               RUNTIME_OUTPUT_DIRECTORY ${out_dir}) # a DLL is a "runtime" output
    if(NOT platform)
      message(STATUS "${name}: FMI ${version}.0 names no platform for ${VI_FMI3_PLATFORM}: the binary only, no FMU")
      continue()
    endif()

    set(fmu ${out_dir}/${name}.fmu)
    set(stage ${CMAKE_CURRENT_BINARY_DIR}/${target}.stage)
    set(merge_binaries "")
    set(merge_fmus "")
    file(RELATIVE_PATH fmu_in_build ${CMAKE_BINARY_DIR} ${fmu})
    foreach(dir ${VI_FMU_MERGE_BINARIES})
      set(other ${dir}/${fmu_in_build})
      if(NOT EXISTS ${other})
        message(STATUS "${name}: no ${other} to take binaries from (no platform name there, or not built)")
        continue()
      endif()
      list(APPEND merge_fmus ${other})
      list(APPEND merge_binaries
        COMMAND ${CMAKE_COMMAND} -E rm -rf ${stage}.other
        COMMAND ${CMAKE_COMMAND} -E make_directory ${stage}.other
        COMMAND ${CMAKE_COMMAND} -E chdir ${stage}.other ${CMAKE_COMMAND} -E tar xf ${other} modelDescription.xml binaries
        COMMAND ${CMAKE_COMMAND} -E compare_files ${version_xml} ${stage}.other/modelDescription.xml
        COMMAND ${CMAKE_COMMAND} -E copy_directory ${stage}.other/binaries ${stage}/binaries
        COMMAND ${CMAKE_COMMAND} -E rm -rf ${stage}.other)
    endforeach()
    set(copy_resources "")
    set(parts modelDescription.xml binaries documentation)
    foreach(f ${ARG_RESOURCES})
      get_filename_component(f ${f} ABSOLUTE)
      list(APPEND copy_resources COMMAND ${CMAKE_COMMAND} -E copy ${f} ${stage}/resources/)
    endforeach()
    if(ARG_RESOURCES)
      list(APPEND parts resources)
    endif()
    # ---- documentation and icon of this version -----------------------------------------------------------
    set(copy_docs COMMAND ${Python3_EXECUTABLE} ${VI_FMU_ROOT}/cmake/vi_fmu_doc.py --fmi ${version}
                  --xml ${version_xml} ${doc_args} ${version_pages} --out ${stage}/documentation
                  --dump ${CMAKE_CROSSCOMPILING_EMULATOR} $<TARGET_FILE:${name}_dump_variables>)
    if(ARG_ICON AND version STREQUAL "2")
      list(APPEND copy_docs COMMAND ${CMAKE_COMMAND} -E copy ${icon} ${stage}/model.png)
      list(APPEND parts model.png)
    elseif(ARG_ICON)
      list(APPEND copy_docs COMMAND ${CMAKE_COMMAND} -E make_directory ${stage}/terminalsAndIcons
                            COMMAND ${CMAKE_COMMAND} -E copy ${icon} ${stage}/terminalsAndIcons/icon.png)
      list(APPEND parts terminalsAndIcons)
    endif()
    # ---- end of documentation and icon ----------------------------------------------------------------------
    add_custom_command(OUTPUT ${fmu}
      COMMAND ${CMAKE_COMMAND} -E rm -rf ${stage}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${stage}/binaries/${platform} ${stage}/resources
      COMMAND ${CMAKE_COMMAND} -E copy ${version_xml} ${stage}/modelDescription.xml
      COMMAND ${CMAKE_COMMAND} -E copy $<TARGET_FILE:${target}> ${stage}/binaries/${platform}/
      ${merge_binaries}
      ${copy_resources}
      ${copy_docs}
      COMMAND ${CMAKE_COMMAND} -E rm -f ${fmu}
      COMMAND ${CMAKE_COMMAND} -E chdir ${stage} ${CMAKE_COMMAND} -E tar cf ${fmu} --format=zip ${parts}
      DEPENDS ${target} ${version_xml} ${ARG_RESOURCES} ${merge_fmus} ${doc_inputs} ${icon} ${name}_dump_variables
      COMMENT "Packing ${name}.fmu (FMI ${version}.0)")
    add_custom_target(${target}_fmu ALL DEPENDS ${fmu})
    add_dependencies(${target}_fmu ${name}_stamp)
  endforeach()
endfunction()
