# Third-party libraries, all from Debian's packages (scripts/install-deps).
# vfsd::thirdparty carries the header-only libraries the engine uses:
# GLM (vector and matrix types), nlohmann/json (scene files) and tinygltf with
# the stb image headers it includes. Both builds compile tinygltf's
# implementation from source (engine/io), so Debian's libtinygltf.so is unused.
add_library(vfsd_thirdparty INTERFACE)
add_library(vfsd::thirdparty ALIAS vfsd_thirdparty)

if(EMSCRIPTEN)
  # Emscripten's sysroot hides /usr/include, and putting /usr/include on emcc's
  # path breaks libc headers: link just the header-only libraries into a folder.
  set(_hdr ${CMAKE_BINARY_DIR}/third_party_include)
  file(MAKE_DIRECTORY ${_hdr})
  foreach(_p glm nlohmann tiny_gltf.h stb_image.h stb_image_write.h)
    if(EXISTS /usr/include/${_p})
      file(CREATE_LINK /usr/include/${_p} ${_hdr}/${_p} SYMBOLIC)
    elseif(EXISTS /usr/include/stb/${_p})
      file(CREATE_LINK /usr/include/stb/${_p} ${_hdr}/${_p} SYMBOLIC)
    else()
      message(FATAL_ERROR "Missing /usr/include/${_p}: run scripts/install-deps")
    endif()
  endforeach()
  target_include_directories(vfsd_thirdparty SYSTEM INTERFACE ${_hdr})
else()
  find_package(glm REQUIRED)
  find_package(nlohmann_json REQUIRED)
  find_package(Threads REQUIRED)
  target_link_libraries(vfsd_thirdparty INTERFACE glm::glm nlohmann_json::nlohmann_json Threads::Threads)
  target_include_directories(vfsd_thirdparty SYSTEM INTERFACE /usr/include/stb)
endif()

# Headless GL for the GPU path's CLI and tests (engine/gpu): Mesa's OSMesa.
if(NOT EMSCRIPTEN)
  find_package(PkgConfig QUIET)
  if(PkgConfig_FOUND)
    pkg_check_modules(OSMESA QUIET IMPORTED_TARGET osmesa)
  endif()
  if(OSMESA_FOUND)
    set(VFSD_OSMESA_FOUND ON)
  else()
    message(STATUS "OSMesa not found (libosmesa6-dev): building without the GPU path")
  endif()
endif()
