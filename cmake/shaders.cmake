# Shader preprocessing without GL, and the build-time check of every shader variant.
#
# drape_shader_source: src/gl/shader_source.cpp on its own (no GL), used by drape_gl, by the pure CPU
# tests and by the host tool drape_glsl_preprocess.
#
# check_shaders (part of ALL): every glsl/sim/*.comp and glsl/render/*.{comp,vert,frag,geom} goes through the
# loader's own preprocessing and `glslangValidator -S <stage>`, once per variant; an error fails the
# build with file:line. Each check has a stamp and a depfile listing every file it included, so a
# variant is checked again only when one of its files changes.
#
# Variants: glsl/<dir>/variants.txt, one variant per line, "<file>: NAME=VALUE NAME ...", e.g.
#   forces_integrate.comp: NUM_SPHERES=1 NUM_PLANES=1 SELF_COLLISION=1
#   forces_integrate.comp: NUM_SPHERES=0 NUM_PLANES=0
#   forces_integrate.comp:
# A bare NAME defines it empty (fine for #ifdef, an error for #if); an empty list means no defines. '#' starts a comment line. A shader with no line is checked once with
# no defines. List enough variants that every #if branch compiles at least once.

add_library(drape_shader_source STATIC ${CMAKE_SOURCE_DIR}/src/gl/shader_source.cpp)
target_include_directories(drape_shader_source PUBLIC ${CMAKE_SOURCE_DIR}/src)
target_compile_definitions(drape_shader_source PRIVATE DRAPE_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
target_link_libraries(drape_shader_source PUBLIC drape_core PRIVATE drape_warnings)  # core/data_dir

# drape_gl globbed shader_source.cpp too; it links the library instead of compiling it twice.
get_target_property(_drape_gl_sources drape_gl SOURCES)
list(REMOVE_ITEM _drape_gl_sources ${CMAKE_SOURCE_DIR}/src/gl/shader_source.cpp)
set_property(TARGET drape_gl PROPERTY SOURCES ${_drape_gl_sources})
target_link_libraries(drape_gl PUBLIC drape_shader_source)

add_executable(drape_glsl_preprocess ${CMAKE_SOURCE_DIR}/tools/glsl_preprocess.cpp)
target_link_libraries(drape_glsl_preprocess PRIVATE drape_shader_source drape_warnings)
target_compile_definitions(drape_glsl_preprocess PRIVATE DRAPE_SOURCE_DIR="${CMAKE_SOURCE_DIR}")

if(NOT GLSLANG_VALIDATOR)
  message(STATUS "glslangValidator not found: shaders are checked only when a context compiles them")
  return()
endif()

set(_glsl_dir ${CMAKE_SOURCE_DIR}/glsl)
file(GLOB _drape_shaders CONFIGURE_DEPENDS
     ${_glsl_dir}/sim/*.comp
     ${_glsl_dir}/render/*.comp ${_glsl_dir}/render/*.vert ${_glsl_dir}/render/*.frag ${_glsl_dir}/render/*.geom)

# Reads glsl/<dir>/variants.txt into _variants_<dir>_<file> lists of define strings.
foreach(_dir sim render)
  set(_variants_file ${_glsl_dir}/${_dir}/variants.txt)
  if(NOT EXISTS ${_variants_file})
    continue()
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_variants_file})
  file(STRINGS ${_variants_file} _lines)
  set(_line_number 0)
  foreach(_line IN LISTS _lines)
    math(EXPR _line_number "${_line_number} + 1")
    string(STRIP "${_line}" _line)
    if(_line STREQUAL "" OR _line MATCHES "^#")
      continue()
    endif()
    if(NOT _line MATCHES "^([A-Za-z0-9_.-]+):(.*)$")
      message(FATAL_ERROR "glsl/${_dir}/variants.txt:${_line_number}: expected '<file>: NAME=VALUE ...', got '${_line}'")
    endif()
    set(_file ${CMAKE_MATCH_1})
    string(STRIP "${CMAKE_MATCH_2}" _defines)
    if(NOT EXISTS ${_glsl_dir}/${_dir}/${_file})
      message(FATAL_ERROR "glsl/${_dir}/variants.txt:${_line_number}: no shader glsl/${_dir}/${_file}")
    endif()
    if(_defines STREQUAL "")
      set(_defines "NONE")  # a list cannot hold an empty element; NONE stands for "no defines"
    endif()
    string(MAKE_C_IDENTIFIER "${_dir}_${_file}" _key)
    list(APPEND _variants_${_key} "${_defines}")
    set(_has_variants_${_key} TRUE)
  endforeach()
endforeach()

set(_stamps)
foreach(_shader IN LISTS _drape_shaders)
  file(RELATIVE_PATH _relative ${_glsl_dir} ${_shader})
  get_filename_component(_dir ${_relative} DIRECTORY)
  get_filename_component(_name ${_relative} NAME)
  string(MAKE_C_IDENTIFIER "${_dir}_${_name}" _key)
  if(_has_variants_${_key})
    set(_variants ${_variants_${_key}})
  else()
    set(_variants "NONE")  # one check without defines
  endif()
  set(_index 0)
  foreach(_variant IN LISTS _variants)
    set(_define_args)
    if(NOT _variant STREQUAL "NONE")
      separate_arguments(_defines UNIX_COMMAND "${_variant}")
      foreach(_define IN LISTS _defines)
        list(APPEND _define_args -D ${_define})
      endforeach()
    endif()
    set(_base ${CMAKE_BINARY_DIR}/shader_check/${_relative}.${_index})
    file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/shader_check/${_dir})
    add_custom_command(
      OUTPUT ${_base}.stamp
      COMMAND drape_glsl_preprocess --root ${_glsl_dir} ${_define_args} --check ${GLSLANG_VALIDATOR}
              --out ${_base}.${_name} --stamp ${_base}.stamp --depfile ${_base}.d ${_shader}
      DEPENDS drape_glsl_preprocess ${_shader}
      DEPFILE ${_base}.d
      COMMENT "Checking glsl/${_relative} (variant ${_index})"
      VERBATIM)
    list(APPEND _stamps ${_base}.stamp)
    math(EXPR _index "${_index} + 1")
  endforeach()
endforeach()

add_custom_target(check_shaders ALL DEPENDS ${_stamps})
