# vi_add_fmu(<Name> SOURCES <model .c files...> XML <modelDescription.xml>
#            [LIBRARIES <libraries...>] [INCLUDE_DIRS <dirs...> (the calling folder is one already)]
#            [RESOURCES <files...>] [DOCUMENTATION <files...>] [OUTPUT_DIRECTORY <dir>])
#
# Builds an FMI 2.0 Co-Simulation FMU of one model on the generic layer (include/vi_fmu.h):
#   <Name>                 the shared library <Name>.so: the model's SOURCES + the layer (src/vi_fmi_core.c, src/vi_fmi2.c); it exports
#                          the fmi2* functions only (static libraries linked in stay hidden) and must
#                          match modelIdentifier="<Name>" in the XML
#   <Name>_fmu (ALL)       packs <OUTPUT_DIRECTORY>/<Name>.fmu (default: the top build directory):
#                          modelDescription.xml, binaries/linux64/<Name>.so, resources/, documentation/
#   <Name>_dump_variables  prints the model's variable table (tests/dump_variables.c), for the test that
#                          compares the table with the XML
# The model's sources must define `const vi_fmu_model vi_fmu_this_model` and its table (vi_table.h).
set(VI_FMU_ROOT ${CMAKE_CURRENT_LIST_DIR}/..)

function(vi_add_fmu name)
  cmake_parse_arguments(ARG "" "XML;OUTPUT_DIRECTORY" "SOURCES;LIBRARIES;INCLUDE_DIRS;RESOURCES;DOCUMENTATION" ${ARGN})
  if(NOT ARG_SOURCES OR NOT ARG_XML)
    message(FATAL_ERROR "vi_add_fmu(${name}): SOURCES and XML are required")
  endif()
  if(NOT ARG_OUTPUT_DIRECTORY)
    set(ARG_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR})
  endif()
  get_filename_component(xml ${ARG_XML} ABSOLUTE)

  # The model without the FMI layer: shared by the FMU binary and the table dump.
  add_library(${name}_model OBJECT ${ARG_SOURCES})
  target_include_directories(${name}_model PUBLIC ${VI_FMU_ROOT}/include ${CMAKE_CURRENT_SOURCE_DIR} ${ARG_INCLUDE_DIRS})
  target_compile_options(${name}_model PRIVATE ${VI_WARNINGS})
  target_link_libraries(${name}_model PUBLIC ${ARG_LIBRARIES} m)
  set_target_properties(${name}_model PROPERTIES C_VISIBILITY_PRESET hidden POSITION_INDEPENDENT_CODE ON)

  add_library(${name} SHARED ${VI_FMU_ROOT}/src/vi_fmi2.c ${VI_FMU_ROOT}/src/vi_fmi_core.c)
  target_include_directories(${name} PRIVATE ${FMI2_HEADERS_DIR} ${VI_FMU_ROOT}/include)
  target_compile_options(${name} PRIVATE ${VI_WARNINGS})
  target_link_libraries(${name} PRIVATE ${name}_model) # an object library: its objects go in
  target_link_options(${name} PRIVATE -Wl,--exclude-libs,ALL -Wl,--no-undefined)
  set_target_properties(${name} PROPERTIES PREFIX "" C_VISIBILITY_PRESET hidden
                                           LIBRARY_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})

  add_executable(${name}_dump_variables ${VI_FMU_ROOT}/tests/dump_variables.c)
  target_compile_options(${name}_dump_variables PRIVATE ${VI_WARNINGS})
  target_link_libraries(${name}_dump_variables PRIVATE ${name}_model)
  set_target_properties(${name}_dump_variables PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})

  set(fmu ${ARG_OUTPUT_DIRECTORY}/${name}.fmu)
  set(stage ${CMAKE_CURRENT_BINARY_DIR}/${name}.stage)
  set(copy_resources "")
  set(copy_docs "")
  set(parts modelDescription.xml binaries)
  foreach(f ${ARG_RESOURCES})
    get_filename_component(f ${f} ABSOLUTE)
    list(APPEND copy_resources COMMAND ${CMAKE_COMMAND} -E copy ${f} ${stage}/resources/)
  endforeach()
  foreach(f ${ARG_DOCUMENTATION})
    get_filename_component(f ${f} ABSOLUTE)
    list(APPEND copy_docs COMMAND ${CMAKE_COMMAND} -E copy ${f} ${stage}/documentation/)
  endforeach()
  if(ARG_RESOURCES)
    list(APPEND parts resources)
  endif()
  if(ARG_DOCUMENTATION)
    list(APPEND parts documentation)
  endif()
  add_custom_command(OUTPUT ${fmu}
    COMMAND ${CMAKE_COMMAND} -E rm -rf ${stage}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${stage}/binaries/linux64 ${stage}/documentation ${stage}/resources
    COMMAND ${CMAKE_COMMAND} -E copy ${xml} ${stage}/modelDescription.xml
    COMMAND ${CMAKE_COMMAND} -E copy $<TARGET_FILE:${name}> ${stage}/binaries/linux64/
    ${copy_resources}
    ${copy_docs}
    COMMAND ${CMAKE_COMMAND} -E rm -f ${fmu}
    COMMAND ${CMAKE_COMMAND} -E chdir ${stage} ${CMAKE_COMMAND} -E tar cf ${fmu} --format=zip ${parts}
    DEPENDS ${name} ${xml} ${ARG_RESOURCES} ${ARG_DOCUMENTATION}
    COMMENT "Packing ${name}.fmu")
  add_custom_target(${name}_fmu ALL DEPENDS ${fmu})
endfunction()
