# The Python module (python/): pybind11 (Debian pybind11-dev) against Debian's /usr/bin/python3 —
# the python3 on PATH may be another interpreter (a pyenv shim) without Debian's numpy and
# nibabel; give -DPython3_EXECUTABLE=… for another. Sets LOBE_PYTHON_MODULE when it is built.
# Not in the sanitizer or fuzz builds (an instrumented module cannot load into an uninstrumented
# interpreter).
set(LOBE_PYTHON_MODULE OFF)
if(LOBE_PYTHON AND NOT LOBE_SANITIZE AND NOT LOBE_FUZZ)
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the module is built for")
  endif()
  find_package(Python3 COMPONENTS Interpreter Development.Module)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 2.6 CONFIG QUIET)
  if(Python3_FOUND AND pybind11_FOUND)
    set(LOBE_PYTHON_MODULE ON)
    # Static libraries linked into a shared object must be position-independent. Without
    # semantic interposition the compiler still inlines and calls directly within a library, as
    # in the default position-independent executables (GCC: -fno-semantic-interposition).
    set(CMAKE_POSITION_INDEPENDENT_CODE ON)
    add_compile_options(-fno-semantic-interposition)
    # Where `cmake --install` puts the module: on Debian's sys.path for the prefixes /usr/local
    # (lib/python3.X/dist-packages) — for any other prefix P, PYTHONPATH=P/<this> (docs/python.md).
    set(LOBE_PYTHON_INSTALL_DIR
        "lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/dist-packages"
        CACHE STRING "Install folder of the Python module, relative to the prefix")
    message(STATUS "Lobe: Python module for ${Python3_EXECUTABLE} (${Python3_VERSION})")
  else()
    message(STATUS "Lobe: no pybind11 or Python development files; the Python module is not built "
                   "(scripts/setup.sh installs pybind11-dev and python3-dev)")
  endif()
endif()
