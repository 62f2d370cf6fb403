# The optional linear solvers of min_style sph/newton, for the in-tree build
# (CMakeLists.txt) and the plugin (plugin/CMakeLists.txt) alike.
#
# esph_find_solvers() sets, in the caller's scope:
#   ESPH_CHOLMOD_DEFINES, ESPH_CHOLMOD_INCLUDE, ESPH_CHOLMOD_LIBS   (empty if not found)
#   ESPH_PETSC_INCLUDE, ESPH_PETSC_LIBS                            (empty if not found)
#   ESPH_PETSC_FILES   the package files that use PETSc (define ESPH_HAVE_PETSC on them)

# min_style sph/newton factorises with SuiteSparse's supernodal CHOLMOD when it
# is found (a BLAS-3 factorisation, several times faster on large Hessians), and
# with Eigen's header-only SimplicialLDLT otherwise.
option(ESPH_CHOLMOD "min_style sph/newton: use SuiteSparse CHOLMOD if found" ON)
# min_style sph/newton's distributed linear solver (min_modify solver petsc or
# mumps) uses PETSc, found through pkg-config (Debian: libpetsc-real-dev,
# built with the same Open MPI as LAMMPS, hypre and MUMPS).  Without it the
# rank-0 solver above is the only one, and asking for PETSc is an error.
option(ESPH_PETSC "min_style sph/newton: use PETSc if found" ON)

macro(esph_find_solvers)
  set(ESPH_CHOLMOD_DEFINES "")
  set(ESPH_CHOLMOD_INCLUDE "")
  set(ESPH_CHOLMOD_LIBS "")
  set(ESPH_PETSC_INCLUDE "")
  set(ESPH_PETSC_LIBS "")
  set(ESPH_PETSC_FILES sph_linear_solver_petsc.cpp sph_petsc_aggregation.cpp)
  if(ESPH_CHOLMOD)
    find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
    find_library(CHOLMOD_LIBRARY cholmod)
    find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
    if(CHOLMOD_INCLUDE_DIR AND CHOLMOD_LIBRARY AND SUITESPARSECONFIG_LIBRARY)
      message(STATUS "ELASTIC-SPH: min_style sph/newton uses CHOLMOD (${CHOLMOD_LIBRARY})")
      set(ESPH_CHOLMOD_DEFINES ESPH_HAVE_CHOLMOD)
      set(ESPH_CHOLMOD_INCLUDE ${CHOLMOD_INCLUDE_DIR})
      set(ESPH_CHOLMOD_LIBS ${CHOLMOD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})
      # CHOLMOD starts OpenMP threads of its own; sph/newton keeps it to one
      # unless OMP_NUM_THREADS asks for more, through the OpenMP runtime's
      # functions (the library only: -fopenmp would change every LAMMPS file)
      # (GCC's libgomp: the runtime Debian's CHOLMOD uses; another compiler's
      # runtime would be a second one in the process)
      find_package(OpenMP COMPONENTS CXX QUIET)
      if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND OpenMP_CXX_FOUND AND OpenMP_CXX_LIBRARIES)
        list(APPEND ESPH_CHOLMOD_DEFINES ESPH_CHOLMOD_OPENMP)
        list(APPEND ESPH_CHOLMOD_LIBS ${OpenMP_CXX_LIBRARIES})
      endif()
    else()
      message(STATUS "ELASTIC-SPH: CHOLMOD not found (Debian: libsuitesparse-dev); "
        "min_style sph/newton uses Eigen's SimplicialLDLT")
    endif()
  endif()
  if(ESPH_PETSC)
    find_package(PkgConfig QUIET)
    if(PKG_CONFIG_FOUND)
      pkg_check_modules(ESPH_PETSC_PC QUIET PETSc)
    endif()
    if(ESPH_PETSC_PC_FOUND)
      message(STATUS "ELASTIC-SPH: min_style sph/newton can solve with PETSc "
        "${ESPH_PETSC_PC_VERSION}")
      set(ESPH_PETSC_INCLUDE ${ESPH_PETSC_PC_INCLUDE_DIRS})
      set(ESPH_PETSC_LIBS ${ESPH_PETSC_PC_LINK_LIBRARIES})
    else()
      message(STATUS "ELASTIC-SPH: PETSc not found (Debian: libpetsc-real-dev); "
        "min_style sph/newton solves on rank 0 only")
    endif()
  endif()
endmacro()
