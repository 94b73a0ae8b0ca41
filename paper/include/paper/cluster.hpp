// The processes of one run: `mpirun -n K nesshi sweep …` starts K of them (rank 0 hands out the
// cells and writes the reports, paper/cell_engine.hpp); any other start is one process. MPI is
// started only when mpirun started us, so a plain `nesshi` never pays for it, and the build
// without OpenMPI has only the one-process cluster.
#pragma once

namespace nesshi::paper {

struct Cluster {
    int rank = 0, size = 1;
    int local_size = 1; // processes on this host (they share its cores)
    bool reports() const { return rank == 0; }
};
// Starts MPI on the first call when started by mpirun (call it from the main thread); MPI ends at exit.
const Cluster& cluster();
// Whether this nesshi was built with MPI.
bool built_with_mpi();

} // namespace nesshi::paper
