// MPI's C API where the program is built with it (STRATUM_HAVE_MPI); without it `stratum sweep`
// runs its samples on one process.
#pragma once

#ifdef STRATUM_HAVE_MPI
#define OMPI_SKIP_MPICXX 1 // the C API only
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif
