# FindFFTW3: FFTW 3 (double precision) with its Fortran 2003 interface.
# Debian: libfftw3-dev (fftw3.f03 in /usr/include, libfftw3.so).
# Looks in FFTW3_ROOT / $FFTW3_ROOT / $FFTW_ROOT first, then the system.
# Sets FFTW3_FOUND, FFTW3_INCLUDE_DIR (the directory of fftw3.f03, for
# Fortran's `include 'fftw3.f03'`), FFTW3_LIBRARY and the imported target
# FFTW3::fftw3.
find_path(FFTW3_INCLUDE_DIR fftw3.f03
          HINTS ${FFTW3_ROOT} ENV FFTW3_ROOT ENV FFTW_ROOT
          PATH_SUFFIXES include)
find_library(FFTW3_LIBRARY NAMES fftw3
             HINTS ${FFTW3_ROOT} ENV FFTW3_ROOT ENV FFTW_ROOT
             PATH_SUFFIXES lib lib64)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(FFTW3 REQUIRED_VARS FFTW3_LIBRARY FFTW3_INCLUDE_DIR
  REASON_FAILURE_MESSAGE
  "FFTW3 with the Fortran 2003 interface (fftw3.f03) is needed: run tools/install-deps.sh as root (Debian: libfftw3-dev), or set FFTW3_ROOT")
if(FFTW3_FOUND AND NOT TARGET FFTW3::fftw3)
  add_library(FFTW3::fftw3 UNKNOWN IMPORTED)
  set_target_properties(FFTW3::fftw3 PROPERTIES IMPORTED_LOCATION "${FFTW3_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${FFTW3_INCLUDE_DIR}")
endif()
mark_as_advanced(FFTW3_INCLUDE_DIR FFTW3_LIBRARY)
