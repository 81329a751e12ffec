# Finds every dependency once, and wraps the ones without imported targets.
# Versions and quirks: ../shared/notes/dependencies.md (Debian 12 packages).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Boost 1.74 REQUIRED COMPONENTS filesystem system)
find_package(yaml-cpp 0.7 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 2.1 REQUIRED)
find_package(fcl 0.7 REQUIRED)
find_package(urdfdom REQUIRED)
