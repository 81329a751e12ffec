# Finds every dependency once, and wraps the ones without imported targets.
# Versions and quirks: ../shared/notes/dependencies.md (Debian 12 packages).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Boost 1.74 REQUIRED COMPONENTS filesystem system)
find_package(yaml-cpp 0.7 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 2.1 REQUIRED)
find_package(fcl 0.7 REQUIRED)
find_package(urdfdom REQUIRED)
# Robot meshes: assimp reads STL, COLLADA and OBJ; qhull makes their convex hulls.
find_package(assimp 5 REQUIRED)
find_package(Qhull REQUIRED)
# URDF checks and MoveIt's SRDF files: TinyXML (what urdfdom reads URDF with; no CMake config).
find_path(CLUTTERTAMP_TINYXML_INCLUDE tinyxml.h)
find_library(CLUTTERTAMP_TINYXML_LIBRARY tinyxml)
if(NOT CLUTTERTAMP_TINYXML_INCLUDE OR NOT CLUTTERTAMP_TINYXML_LIBRARY)
  message(FATAL_ERROR "TinyXML not found: install libtinyxml-dev (scripts/install-deps.sh)")
endif()
# Wraps a package found in module mode (include directories and libraries in
# variables) as an INTERFACE target whose headers are SYSTEM headers.
function(cluttertamp_wrap_package target include_dirs libraries)
  if(NOT TARGET ${target})
    add_library(${target} INTERFACE)
    target_include_directories(${target} SYSTEM INTERFACE ${include_dirs})
    target_link_libraries(${target} INTERFACE ${libraries})
  endif()
endfunction()
cluttertamp_wrap_package(cluttertamp_tinyxml "${CLUTTERTAMP_TINYXML_INCLUDE}" "${CLUTTERTAMP_TINYXML_LIBRARY}")
# OMPL has no imported target. Physics and plugins only.
find_package(ompl 1.5 REQUIRED)
cluttertamp_wrap_package(cluttertamp_ompl "${OMPL_INCLUDE_DIRS}" "${OMPL_LIBRARIES}")
# Bullet: module mode (Debian's config file has broken relative paths); single
# precision. The physics layer only.
find_package(Bullet REQUIRED)
cluttertamp_wrap_package(cluttertamp_bullet "${BULLET_INCLUDE_DIRS}" "${BULLET_LIBRARIES}")
# The browser side (`cluttertamp view`, `cluttertamp guide`): cpp-httplib (Debian builds
# it as a shared library; its pkg-config flags enable TLS, which we do not use) for the
# browser tests' client; the guide server is Boost.Beast, beside Boost.Asio; and
# three.js from libjs-three, inlined into every plan page. The CLI only.
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib>=0.11)
find_path(CLUTTERTAMP_THREE_JS_DIR build/three.min.js PATHS /usr/share/javascript/three NO_DEFAULT_PATH)
if(NOT CLUTTERTAMP_THREE_JS_DIR)
  message(FATAL_ERROR "three.js not found in /usr/share/javascript/three: install libjs-three (scripts/install-deps.sh)")
endif()
find_package(Threads REQUIRED)
# The Python module: pybind11 for Debian's interpreter (/usr/bin/python3, the one apt's
# python3-numpy and python3-pytest serve; another with -DPython3_EXECUTABLE=...).
if(CLUTTERTAMP_BUILD_PYTHON)
  if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 3.9 REQUIRED COMPONENTS Interpreter Development.Module NumPy)
  find_package(pybind11 2.6 CONFIG)
  if(NOT pybind11_FOUND)
    message(FATAL_ERROR "pybind11 not found: install pybind11-dev python3-numpy python3-pytest (scripts/install-deps.sh), "
                        "or configure with -DCLUTTERTAMP_BUILD_PYTHON=OFF")
  endif()
endif()
