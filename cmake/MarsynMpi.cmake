# MPI (docs/mpi.md): `mpirun -np R marsyn solve ...` spreads one solve over R ranks. On by
# default when an MPI implementation is found (Debian: libopenmpi-dev); without it, or with
# -DMARSYN_WITH_MPI=OFF, marsyn builds and runs as a single process, exactly as before.
option(MARSYN_WITH_MPI "Run solve over MPI ranks when launched by mpirun/srun (needs MPI)" ON)
set(MARSYN_HAVE_MPI OFF)
if(MARSYN_WITH_MPI)
  find_package(MPI COMPONENTS CXX QUIET)
  if(MPI_CXX_FOUND)
    set(MARSYN_HAVE_MPI ON)
    message(STATUS "marsyn: MPI found (MPI ${MPI_CXX_VERSION}): solve runs over ranks under mpirun/srun")
  else()
    message(STATUS "marsyn: MPI not found: single-process build (install libopenmpi-dev for MPI)")
  endif()
endif()
find_program(MARSYN_MPIEXEC NAMES mpirun mpiexec)

# Links MPI into `target` (core only: plugins see marsyn::Collective, never MPI) and defines
# MARSYN_HAVE_MPI for its sources.
function(marsyn_use_mpi target)
  if(MARSYN_HAVE_MPI)
    target_link_libraries(${target} PRIVATE MPI::MPI_CXX)
    target_compile_definitions(${target} PRIVATE MARSYN_HAVE_MPI=1)
  endif()
endfunction()
