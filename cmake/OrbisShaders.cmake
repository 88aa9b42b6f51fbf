# Compiles GLSL to SPIR-V at build time and wraps each module in a C++ header
# (const uint32_t array), so binaries never look for shaders on disk.
#
#   orbis_add_shaders(TARGET name SOURCES a.vert b.frag ...)
# creates an INTERFACE library `name`; linking it adds the include folder. A shader
# shaders/globe/ellipsoid.vert becomes  #include "spv/earth/ellipsoid.vert.h"  with the array
# kSpv_earth_ellipsoid_vert.
function(orbis_add_shaders)
  cmake_parse_arguments(ARG "" "TARGET" "SOURCES" ${ARGN})
  set(out_root ${CMAKE_BINARY_DIR}/shaders/include)
  # Included files: the C++/GLSL headers in shared/ and GLSL-only pieces (*.glsl) of any layer.
  file(GLOB shared_headers CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/shaders/shared/*.h ${PROJECT_SOURCE_DIR}/shaders/*/*.glsl)
  set(outputs)
  foreach(src ${ARG_SOURCES})
    get_filename_component(abs ${src} ABSOLUTE)
    file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR}/shaders ${abs})
    string(REGEX REPLACE "[/.]" "_" var ${rel})
    set(out ${out_root}/spv/${rel}.h)
    get_filename_component(out_dir ${out} DIRECTORY)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${out_dir}
      COMMAND Vulkan::glslangValidator -V --quiet --target-env vulkan1.2
              -I${PROJECT_SOURCE_DIR}/shaders --vn kSpv_${var} -o ${out} ${abs}
      DEPENDS ${abs} ${shared_headers}
      COMMENT "glslang ${rel}"
      VERBATIM)
    list(APPEND outputs ${out})
  endforeach()
  add_custom_target(${ARG_TARGET}_spirv DEPENDS ${outputs})
  add_library(${ARG_TARGET} INTERFACE)
  target_include_directories(${ARG_TARGET} INTERFACE ${out_root} ${PROJECT_SOURCE_DIR})
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_spirv)
endfunction()
