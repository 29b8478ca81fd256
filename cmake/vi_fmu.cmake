# vi_add_fmu(<Name> SOURCES <model .c files...>
#            [FMI_VERSIONS <2 and/or 3> (default 2)]
#            [LIBRARIES <libraries...>] [INCLUDE_DIRS <dirs...> (the calling folder is one already)]
#            [RESOURCES <files...>] [OUTPUT_DIRECTORY <dir>]
#            [DOC_INTRO <README.md>] [DOCUMENTATION <pages.md...>] [DOCUMENTATION_FMI3 <pages.md...>]
#            [LICENSES <NAME=file>...] [ICON <png>] [GENERATION_TOOL <text>])
#
# Builds Co-Simulation and Model Exchange FMUs of one model on the generic layer (src/fmi/vi_fmu.h), one
# per FMI version, all from the same compiled model (<Name>_model). Both model descriptions are
# generated from the model's variable table (cmake/vi_model_description.py reading <Name>_dump_variables)
# and stamped with the release (cmake/vi_fmu_stamp.py: version, generationDateAndTime, copyright, license;
# generationTool when GENERATION_TOOL is given, e.g. what the binaries carry):
#   FMI 2.0:
#     <Name>               the shared library <Name>.so (.dll on Windows): the model + the layer
#                          (VI_FMU_LAYER_SOURCES and the FMI 2.0 face src/fmi/vi_fmi2.c), exporting the fmi2*
#                          functions only (static libraries linked in stay hidden); VI_MODEL_IDENTIFIER
#                          of the table must be <Name>
#     <Name>_fmu (ALL)     packs <OUTPUT_DIRECTORY>/<Name>.fmu (default: the top build directory):
#                          modelDescription.xml, binaries/<VI_FMI2_PLATFORM>/<Name>.so, resources/,
#                          documentation/_main.html, model.png (ICON) (no FMU where FMI 2.0 names no
#                          platform: aarch64 Linux)
#   FMI 3.0:
#     <Name>_fmi3          the shared library <OUTPUT_DIRECTORY>/fmi3/<Name>.so: the model + the layer
#                          (VI_FMU_LAYER_SOURCES and the FMI 3.0 face src/fmi/vi_fmi3.c), exporting the fmi3*
#                          functions only
#     <Name>_fmi3_fmu (ALL) packs <OUTPUT_DIRECTORY>/fmi3/<Name>.fmu: modelDescription.xml,
#                          binaries/<VI_FMI3_PLATFORM>/<Name>.so, resources/, documentation/index.html,
#                          terminalsAndIcons/icon.png (ICON)
#   <Name>_dump_variables  prints the model's variable table (tests/dump_variables.c): the source of the
#                          model descriptions, of the documentation's variable table and of the tests
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
# --- source FMUs ---
# VI_FMU_SUNDIALS_SOURCES (cache, SUNDIALS' source tree, tools/release.sh): each FMU packed here also
# holds sources/, everything an importer needs to compile its binary with no SUNDIALS installed
# (cmake/vi_fmu_sources.py: the model's C files, the layer, the CVODE sources it uses, a
# configuration header for any platform), listed in <SourceFiles> of the FMI 2.0 model description
# and in sources/buildDescription.xml for FMI 3.0.
# --- end source FMUs ---
set(VI_FMU_ROOT ${CMAKE_CURRENT_LIST_DIR}/..)
# The layer's headers (src/fmi) and what it shares with every layer (src/base: checks, numbers as text).
set(VI_FMU_LAYER_INCLUDE_DIRS ${VI_FMU_ROOT}/src/fmi ${VI_FMU_ROOT}/src/base)
# The generic FMI layer that every face builds on (src/fmi/vi_fmu.h, src/fmi/vi_fmi_layer.h): the files
# shared by both versions, one concern each.
set(VI_FMU_LAYER_SOURCES
    ${VI_FMU_ROOT}/src/fmi/vi_fmi_state_machine.c ${VI_FMU_ROOT}/src/fmi/vi_fmi_log.c ${VI_FMU_ROOT}/src/fmi/vi_fmi_instance.c
    ${VI_FMU_ROOT}/src/fmi/vi_fmi_values.c ${VI_FMU_ROOT}/src/fmi/vi_fmi_fmu_state.c ${VI_FMU_ROOT}/src/fmi/vi_fmi_cosim.c
    ${VI_FMU_ROOT}/src/fmi/vi_fmi_model_exchange.c)
include(${CMAKE_CURRENT_LIST_DIR}/vi_platform.cmake)
set(VI_FMU_MERGE_BINARIES "" CACHE STRING
    "Build directories of other platforms whose FMU binaries the FMUs packed here also hold")
# --- source FMUs ---
set(VI_FMU_SUNDIALS_SOURCES "" CACHE PATH "SUNDIALS' source tree: the FMUs packed here also hold sources/")

# vi_fmu_stage_sources(<name> <fmi version> <model XML> <out: model XML to pack> <out: sources folder>
#                      <out: files the staging depends on> <C files...>): the custom command writing
# <folder>/sources (and, FMI 2.0, the model description with <SourceFiles>); nothing without
# VI_FMU_SUNDIALS_SOURCES. Uses ARG_INCLUDE_DIRS and ARG_LIBRARIES of vi_add_fmu().
function(vi_fmu_stage_sources name version xml xml_out dir_out depends_out)
  set(${xml_out} ${xml} PARENT_SCOPE)
  set(${dir_out} "" PARENT_SCOPE)
  set(${depends_out} "" PARENT_SCOPE)
  if(NOT VI_FMU_SUNDIALS_SOURCES)
    return()
  endif()
  set(c_files "")
  foreach(f ${ARGN})
    get_filename_component(f ${f} ABSOLUTE)
    list(APPEND c_files ${f})
  endforeach()
  foreach(lib ${ARG_LIBRARIES} vi_text) # the libraries' own C files (vi_simulator, vt_solver; vi_text, the layer's)
    if(TARGET ${lib})
      get_target_property(lib_sources ${lib} SOURCES)
      get_target_property(lib_dir ${lib} SOURCE_DIR)
      foreach(f ${lib_sources})
        get_filename_component(f ${f} ABSOLUTE BASE_DIR ${lib_dir})
        list(APPEND c_files ${f})
      endforeach()
    endif()
  endforeach()
  list(REMOVE_DUPLICATES c_files)
  set(include_dirs ${VI_FMU_LAYER_INCLUDE_DIRS} ${CMAKE_CURRENT_SOURCE_DIR} ${ARG_INCLUDE_DIRS})
  foreach(lib ${ARG_LIBRARIES}) # the folders the libraries' headers are in (vi_simulator: every layer's)
    if(TARGET ${lib})
      get_target_property(lib_includes ${lib} INTERFACE_INCLUDE_DIRECTORIES)
      if(lib_includes)
        list(APPEND include_dirs ${lib_includes})
      endif()
    endif()
  endforeach()
  list(REMOVE_DUPLICATES include_dirs)
  set(headers "")
  foreach(d ${include_dirs})
    file(GLOB h ${d}/*.h)
    list(APPEND headers ${h})
  endforeach()
  file(GLOB tables ${VI_FMU_ROOT}/src/*/*.inc) # the tables the C files include (vi_laws.c: vi_tsuji_table.inc)
  list(APPEND headers ${tables})
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmi${version}.sources)
  set(script ${VI_FMU_ROOT}/cmake/vi_fmu_sources.py)
  set(args --out ${dir}/sources --sundials ${VI_FMU_SUNDIALS_SOURCES} --fmi-headers ${FMI2_HEADERS_DIR}
           --sources ${c_files} --include-dirs ${include_dirs})
  if(version STREQUAL "2")
    set(${xml_out} ${dir}/modelDescription.xml PARENT_SCOPE)
    list(APPEND args --fmi2-xml ${xml} --fmi2-xml-out ${dir}/modelDescription.xml)
    set(outputs ${dir}/modelDescription.xml)
  else()
    list(APPEND args --build-description ${name} --define VI_FMI3_TIME_VR=${VI_FMI3_TIME_VR}u
                     VI_FMI3_DERIVATIVE_VR_BASE=${VI_FMI3_DERIVATIVE_VR_BASE}u
                     VI_FMI3_INDICATOR_VR_BASE=${VI_FMI3_INDICATOR_VR_BASE}u)
    set(outputs ${dir}/sources/buildDescription.xml)
  endif()
  add_custom_command(OUTPUT ${outputs}
    COMMAND ${Python3_EXECUTABLE} ${script} ${args}
    DEPENDS ${script} ${xml} ${c_files} ${headers}
    COMMENT "Writing the sources/ of ${name}.fmu (FMI ${version}.0)")
  set(${dir_out} ${dir}/sources PARENT_SCOPE)
  set(${depends_out} ${outputs} PARENT_SCOPE)
endfunction()
# --- end source FMUs ---
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

# vi_fmu_description(<name> <fmi version> <out: the stamped modelDescription.xml> [<generationTool>]): the
# custom commands that generate the model description of that version from <name>_dump_variables
# (cmake/vi_model_description.py, <folder>/<name>_fmi<version>/generated.xml) and stamp it with the
# release (cmake/vi_fmu_stamp.py, <folder>/<name>_fmi<version>/modelDescription.xml).
function(vi_fmu_description name version xml_out)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmi${version})
  set(tool_args "")
  if(ARGN)
    set(tool_args "--generation-tool=${ARGN}")
  endif()
  # a file that changes when the text does, so that the description is stamped again
  set(tool_file ${dir}/generation_tool.txt)
  set(tool_old "none")
  if(EXISTS ${tool_file})
    file(READ ${tool_file} tool_old)
  endif()
  if(NOT tool_old STREQUAL "${ARGN}")
    file(WRITE ${tool_file} "${ARGN}")
  endif()
  set(generator ${VI_FMU_ROOT}/cmake/vi_model_description.py)
  set(stamper ${VI_FMU_ROOT}/cmake/vi_fmu_stamp.py)
  set(fmi3_args "")
  if(version STREQUAL "3")
    set(fmi3_args --time-vr ${VI_FMI3_TIME_VR} --derivative-vr-base ${VI_FMI3_DERIVATIVE_VR_BASE}
                  --indicator-vr-base ${VI_FMI3_INDICATOR_VR_BASE})
  elseif(NOT version STREQUAL "2")
    message(FATAL_ERROR "vi_add_fmu(${name}): FMI_VERSIONS ${version}: use 2 and/or 3")
  endif()
  add_custom_command(OUTPUT ${dir}/modelDescription.xml
    COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}
    COMMAND ${Python3_EXECUTABLE} ${generator} --fmi ${version} ${fmi3_args} --out ${dir}/generated.xml
            --dump ${CMAKE_CROSSCOMPILING_EMULATOR} $<TARGET_FILE:${name}_dump_variables>
    COMMAND ${Python3_EXECUTABLE} ${stamper} --xml ${dir}/generated.xml --version ${PROJECT_VERSION}
            --source-date-epoch=$ENV{SOURCE_DATE_EPOCH} --license ${VI_FMU_ROOT}/LICENSE --out ${dir}/modelDescription.xml
            ${tool_args}
    DEPENDS ${generator} ${stamper} ${name}_dump_variables ${VI_FMU_ROOT}/LICENSE ${VI_FMU_RELEASE_STAMP} ${tool_file}
    COMMENT "Generating the FMI ${version}.0 modelDescription.xml of ${name} (version ${PROJECT_VERSION})")
  set(${xml_out} ${dir}/modelDescription.xml PARENT_SCOPE)
endfunction()

function(vi_add_fmu name)
  cmake_parse_arguments(ARG "" "OUTPUT_DIRECTORY;DOC_INTRO;ICON;GENERATION_TOOL"
                        "SOURCES;LIBRARIES;INCLUDE_DIRS;RESOURCES;FMI_VERSIONS;DOCUMENTATION;DOCUMENTATION_FMI3;LICENSES"
                        ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "vi_add_fmu(${name}): SOURCES are required")
  endif()
  if(NOT ARG_OUTPUT_DIRECTORY)
    set(ARG_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR})
  endif()
  if(NOT ARG_FMI_VERSIONS)
    set(ARG_FMI_VERSIONS 2)
  endif()

  # The model without the FMI layer: shared by the FMU binaries and the table dump.
  add_library(${name}_model OBJECT ${ARG_SOURCES})
  target_include_directories(${name}_model PUBLIC ${VI_FMU_LAYER_INCLUDE_DIRS} ${CMAKE_CURRENT_SOURCE_DIR} ${ARG_INCLUDE_DIRS})
  target_compile_options(${name}_model PRIVATE ${VI_WARNINGS})
  target_link_libraries(${name}_model PUBLIC ${ARG_LIBRARIES} vi_text m) # the layer formats with vi_text
  set_target_properties(${name}_model PROPERTIES C_VISIBILITY_PRESET hidden POSITION_INDEPENDENT_CODE ON)

  add_executable(${name}_dump_variables ${VI_FMU_ROOT}/tests/dump_variables.c)
  target_compile_options(${name}_dump_variables PRIVATE ${VI_WARNINGS})
  target_link_libraries(${name}_dump_variables PRIVATE ${name}_model)
  set_target_properties(${name}_dump_variables PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})

  # ---- the model descriptions, generated from the table and stamped with the release ------------------
  foreach(version ${ARG_FMI_VERSIONS})
    vi_fmu_description(${name} ${version} xml_${version} ${ARG_GENERATION_TOOL})
  endforeach()
  set(doc_args --license ${VI_FMU_ROOT}/LICENSE)
  set(doc_inputs ${VI_FMU_ROOT}/cmake/vi_fmu_doc.py ${VI_FMU_ROOT}/cmake/vi_model_description.py ${VI_FMU_ROOT}/LICENSE)
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
      set(face ${VI_FMU_ROOT}/src/fmi/vi_fmi2.c)
      set(platform ${VI_FMI2_PLATFORM})
      set(out_dir ${ARG_OUTPUT_DIRECTORY})
      set(version_xml ${xml_2})
      set(version_pages ${doc_DOCUMENTATION})
      set(defs "")
    elseif(version STREQUAL "3")
      set(target ${name}_fmi3)
      set(face ${VI_FMU_ROOT}/src/fmi/vi_fmi3.c)
      set(platform ${VI_FMI3_PLATFORM})
      set(out_dir ${ARG_OUTPUT_DIRECTORY}/fmi3)
      set(version_xml ${xml_3})
      set(defs VI_FMI3_TIME_VR=${VI_FMI3_TIME_VR}u VI_FMI3_DERIVATIVE_VR_BASE=${VI_FMI3_DERIVATIVE_VR_BASE}u
               VI_FMI3_INDICATOR_VR_BASE=${VI_FMI3_INDICATOR_VR_BASE}u)
      set(version_pages ${doc_DOCUMENTATION} ${doc_DOCUMENTATION_FMI3})
    else()
      message(FATAL_ERROR "vi_add_fmu(${name}): FMI_VERSIONS ${version}: use 2 and/or 3")
    endif()

    add_library(${target} SHARED ${face} ${VI_FMU_LAYER_SOURCES})
    target_include_directories(${target} PRIVATE ${FMI2_HEADERS_DIR} ${VI_FMU_LAYER_INCLUDE_DIRS})
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
    # --- source FMUs ---
    vi_fmu_stage_sources(${name} ${version} ${version_xml} version_xml sources_dir sources_depends
                         ${ARG_SOURCES} ${face} ${VI_FMU_LAYER_SOURCES})
    set(copy_sources "")
    if(sources_dir)
      set(copy_sources COMMAND ${CMAKE_COMMAND} -E copy_directory ${sources_dir} ${stage}/sources)
    endif()
    # --- end source FMUs ---
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
    if(sources_dir) # source FMUs
      list(APPEND parts sources)
    endif()
    add_custom_command(OUTPUT ${fmu}
      COMMAND ${CMAKE_COMMAND} -E rm -rf ${stage}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${stage}/binaries/${platform} ${stage}/resources
      COMMAND ${CMAKE_COMMAND} -E copy ${version_xml} ${stage}/modelDescription.xml
      COMMAND ${CMAKE_COMMAND} -E copy $<TARGET_FILE:${target}> ${stage}/binaries/${platform}/
      ${merge_binaries}
      ${copy_resources}
      ${copy_docs}
      ${copy_sources}
      COMMAND ${CMAKE_COMMAND} -E rm -f ${fmu}
      COMMAND ${CMAKE_COMMAND} -E chdir ${stage} ${CMAKE_COMMAND} -E tar cf ${fmu} --format=zip ${parts}
      DEPENDS ${target} ${version_xml} ${ARG_RESOURCES} ${merge_fmus} ${doc_inputs} ${icon} ${name}_dump_variables
              ${sources_depends}
      COMMENT "Packing ${name}.fmu (FMI ${version}.0)")
    add_custom_target(${target}_fmu ALL DEPENDS ${fmu})
  endforeach()
endfunction()
