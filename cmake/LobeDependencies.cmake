# Every dependency is a Debian 12 package (see scripts/setup.sh); the traps are in docs/dependencies.md.

# oneTBB must be found before OpenVDB, whose FindOpenVDB would otherwise look for the old TBB.
find_package(TBB 2021 CONFIG REQUIRED COMPONENTS tbb)
find_package(Imath CONFIG REQUIRED)
find_package(embree 3 CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(nlohmann_json 3 CONFIG REQUIRED)
find_package(ZLIB REQUIRED)
# Google Highway: portable SIMD with runtime dispatch (volume/dvr_simd.h).
find_package(hwy CONFIG REQUIRED)
# cpp-httplib (Debian libcpp-httplib-dev) for `lobe study serve`: Debian builds it as a library
# (libcpp-httplib.so) whose pkg-config flags select its TLS/compression options; use them.
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)

# Debian ships FindOpenVDB.cmake outside CMake's default module path.
list(APPEND CMAKE_MODULE_PATH /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB)
find_package(OpenVDB 10 REQUIRED)
# FindOpenVDB sets BUILD_SHARED_LIBS=ON in our scope; every add_library below names STATIC explicitly.

find_package(OpenImageIO 2.4 CONFIG REQUIRED)
# Debian's OpenImageIO target lists /usr/include/opencv4, which does not exist: drop it or generate fails.
foreach(prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(dirs OpenImageIO::OpenImageIO ${prop})
  if(dirs)
    list(FILTER dirs EXCLUDE REGEX "opencv4$")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${prop} "${dirs}")
  endif()
endforeach()

# Captions are drawn with FreeType (figure/image_text.cpp; Debian libfreetype-dev): OpenImageIO's
# render_text garbles every non-ASCII character.
find_package(Freetype REQUIRED)

if(LOBE_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
  include(GoogleTest)
endif()
if(LOBE_BUILD_BENCHMARKS)
  find_package(benchmark CONFIG REQUIRED)
endif()

# Open MPI (Debian libopenmpi-dev) is optional: found → `lobe render` shares tiles across the
# processes of an mpirun (cluster/cluster.h); absent → lobe works as a single process.
option(LOBE_WITH_MPI "Build MPI support when an MPI library is found" ON)
if(LOBE_WITH_MPI)
  set(MPI_CXX_SKIP_MPICXX ON)  # the C API only; no C++ bindings
  find_package(MPI COMPONENTS CXX)
endif()
find_program(LOBE_MPIEXEC NAMES mpirun mpiexec)
