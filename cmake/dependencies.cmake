# Third-party libraries, all from Debian's packages (scripts/install-deps).
# vfsd::thirdparty carries the header-only libraries the engine uses:
# GLM (vector and matrix types), nlohmann/json (scene files), Eigen (the sparse
# solver of the harmonic blend profile, region/harmonic_blend.h) and tinygltf with
# the stb image headers it includes. Both builds compile tinygltf's
# implementation from source (engine/io), so Debian's libtinygltf.so is unused.
add_library(vfsd_thirdparty INTERFACE)
add_library(vfsd::thirdparty ALIAS vfsd_thirdparty)

if(EMSCRIPTEN)
  # Emscripten's sysroot hides /usr/include, and putting /usr/include on emcc's
  # path breaks libc headers: link just the header-only libraries into a folder.
  set(_hdr ${CMAKE_BINARY_DIR}/third_party_include)
  file(MAKE_DIRECTORY ${_hdr})
  foreach(_p glm nlohmann Eigen tiny_gltf.h stb_image.h stb_image_write.h)
    if(EXISTS /usr/include/${_p})
      file(CREATE_LINK /usr/include/${_p} ${_hdr}/${_p} SYMBOLIC)
    elseif(EXISTS /usr/include/eigen3/${_p})
      file(CREATE_LINK /usr/include/eigen3/${_p} ${_hdr}/${_p} SYMBOLIC)
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
  find_package(Eigen3 3.3 REQUIRED NO_MODULE)
  target_link_libraries(vfsd_thirdparty INTERFACE glm::glm nlohmann_json::nlohmann_json Eigen3::Eigen Threads::Threads)
  target_include_directories(vfsd_thirdparty SYSTEM INTERFACE /usr/include/stb)
endif()

# Headless GL for the GPU path's CLI and tests (engine/gpu), chosen at configure
# time because one binary never links two GL libraries: VFSD_HEADLESS_GL=osmesa
# (default: Mesa's OSMesa, llvmpipe) or egl (glvnd's libEGL + libOpenGL: a GPU
# driver's EGL device, or Mesa's surfaceless platform; preset release-egl).
set(VFSD_HEADLESS_GL "osmesa" CACHE STRING "Headless GL context of the CLI and tests: osmesa or egl")
set_property(CACHE VFSD_HEADLESS_GL PROPERTY STRINGS osmesa egl)
if(NOT EMSCRIPTEN AND VFSD_HEADLESS_GL STREQUAL "egl")
  find_package(OpenGL COMPONENTS EGL OpenGL)
  if(NOT TARGET OpenGL::EGL OR NOT TARGET OpenGL::OpenGL)
    message(FATAL_ERROR "VFSD_HEADLESS_GL=egl needs glvnd's libEGL and libOpenGL: "
                        "install libegl-dev and libopengl-dev (scripts/build-egl does)")
  endif()
  set(VFSD_EGL_FOUND ON)
elseif(NOT EMSCRIPTEN AND VFSD_HEADLESS_GL STREQUAL "osmesa")
  find_package(PkgConfig QUIET)
  if(PkgConfig_FOUND)
    pkg_check_modules(OSMESA QUIET IMPORTED_TARGET osmesa)
  endif()
  if(NOT OSMESA_FOUND)
    message(FATAL_ERROR "OSMesa not found: install libosmesa6-dev (scripts/install-deps does), or configure "
                        "with -DVFSD_HEADLESS_GL=egl")
  endif()
  set(VFSD_OSMESA_FOUND ON)
elseif(NOT EMSCRIPTEN)
  message(FATAL_ERROR "VFSD_HEADLESS_GL='${VFSD_HEADLESS_GL}': expected osmesa or egl")
endif()
