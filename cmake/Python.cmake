# The Python module (validate/python/) and its pytest suite (tests/python/):
# built where Python's headers, pybind11 and NumPy are found. WARPCHECK_PYTHON:
#   AUTO (default) builds it when they are found, except under the sanitizers
#        (an instrumented extension cannot load into an uninstrumented python3);
#   ON   requires them (a missing one stops the configuration with its Debian package);
#   OFF  leaves it out.
# The interpreter is Debian's /usr/bin/python3 where it exists (Python3_EXECUTABLE
# chooses another): a pyenv or venv python3 first on PATH has no Debian packages.
set(WARPCHECK_PYTHON AUTO CACHE STRING "Build the Python module: AUTO, ON or OFF")
set_property(CACHE WARPCHECK_PYTHON PROPERTY STRINGS AUTO ON OFF)
set(WARPCHECK_PYTHON_BUILT OFF)
if(WARPCHECK_PYTHON STREQUAL "OFF" OR (WARPCHECK_PYTHON STREQUAL "AUTO" AND WARPCHECK_SANITIZE))
  message(STATUS "Python module: not built (WARPCHECK_PYTHON=${WARPCHECK_PYTHON}${WARPCHECK_SANITIZE})")
  return()
endif()
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the module is built for and pytest runs with")
endif()
find_package(Python3 3.9 QUIET COMPONENTS Interpreter Development.Module NumPy)
if(Python3_FOUND)
  find_package(pybind11 2.6 CONFIG QUIET)
endif()
set(missing "")
if(NOT Python3_Development.Module_FOUND)
  list(APPEND missing python3-dev)
endif()
if(NOT Python3_NumPy_FOUND)
  list(APPEND missing python3-numpy)
endif()
if(NOT pybind11_FOUND)
  list(APPEND missing pybind11-dev)
endif()
if(missing)
  list(JOIN missing " " packages)
  if(WARPCHECK_PYTHON STREQUAL "ON")
    message(FATAL_ERROR "WARPCHECK_PYTHON=ON, but the Python module needs what was not found for "
                        "${Python3_EXECUTABLE}.\nOn Debian 12 install it with:  apt-get install ${packages}\n"
                        "(or run .ci/install-deps)")
  endif()
  message(STATUS "Python module: not built (apt-get install ${packages} for it)")
  return()
endif()
set(WARPCHECK_PYTHON_BUILT ON)
message(STATUS "Python module: built for ${Python3_EXECUTABLE} (Python ${Python3_VERSION}, NumPy ${Python3_NumPy_VERSION}, pybind11 ${pybind11_VERSION})")
