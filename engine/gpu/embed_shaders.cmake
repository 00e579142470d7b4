# cmake -DOUT=file.cpp -DFILES="a|b|..." -P embed_shaders.cmake
# Writes the given shader files into a C++ table of {name, text} (raw strings).
string(REPLACE "|" ";" FILES "${FILES}")
set(_body "// Generated from shaders/ by engine/gpu/embed_shaders.cmake; do not edit.\n#include \"gpu/shader_sources.h\"\n\nnamespace vfsd::gpu::detail {\n\nextern const EmbeddedShader kEmbeddedShaders[] = {\n")
foreach(_file IN LISTS FILES)
  get_filename_component(_name ${_file} NAME)
  file(READ ${_file} _text)
  string(APPEND _body "    {\"${_name}\", R\"vfsd_glsl(${_text})vfsd_glsl\"},\n")
endforeach()
list(LENGTH FILES _count)
string(APPEND _body "};\nextern const std::size_t kEmbeddedShaderCount = ${_count};\n\n}  // namespace vfsd::gpu::detail\n")
# Rewrite only on change, so an unchanged shader set does not rebuild.
if(EXISTS ${OUT})
  file(READ ${OUT} _old)
  if(_old STREQUAL _body)
    return()
  endif()
endif()
file(WRITE ${OUT} "${_body}")
