# Finds every dependency once, and wraps the ones without imported targets.
# Versions and quirks: ../shared/notes/dependencies.md (Debian 12 packages).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Boost 1.74 REQUIRED COMPONENTS filesystem system)
find_package(yaml-cpp 0.7 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 2.1 REQUIRED)
find_package(fcl 0.7 REQUIRED)
find_package(urdfdom REQUIRED)
# OMPL has no imported target: wrap its variables, headers as SYSTEM. Plugins only.
find_package(ompl 1.5 REQUIRED)
if(NOT TARGET cluttertamp_ompl)
  add_library(cluttertamp_ompl INTERFACE)
  target_include_directories(cluttertamp_ompl SYSTEM INTERFACE ${OMPL_INCLUDE_DIRS})
  target_link_libraries(cluttertamp_ompl INTERFACE ${OMPL_LIBRARIES})
endif()
# Bullet: module mode (Debian's config file has broken relative paths); single
# precision. Wrapped like OMPL, headers as SYSTEM; the core library's physics/ only.
find_package(Bullet REQUIRED)
if(NOT TARGET cluttertamp_bullet)
  add_library(cluttertamp_bullet INTERFACE)
  target_include_directories(cluttertamp_bullet SYSTEM INTERFACE ${BULLET_INCLUDE_DIRS})
  target_link_libraries(cluttertamp_bullet INTERFACE ${BULLET_LIBRARIES})
endif()
# The browser side (`cluttertamp view`, `cluttertamp guide`): cpp-httplib (Debian builds
# it as a shared library; its pkg-config flags enable TLS, which we do not use) and
# three.js from libjs-three, inlined into every plan page. The CLI only.
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib>=0.11)
find_path(CLUTTERTAMP_THREE_JS_DIR build/three.min.js PATHS /usr/share/javascript/three NO_DEFAULT_PATH)
if(NOT CLUTTERTAMP_THREE_JS_DIR)
  message(FATAL_ERROR "three.js not found in /usr/share/javascript/three: install libjs-three (scripts/install-deps.sh)")
endif()
find_package(Threads REQUIRED)
