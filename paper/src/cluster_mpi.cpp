// The cluster of an MPI build: MPI starts only when mpirun (OpenMPI, or a PMI launcher) started us.
#include "paper/cluster.hpp"

#include <mpi.h>

#include <cstdlib>

namespace nesshi::paper {

namespace {

bool started_by_mpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") || std::getenv("PMI_RANK");
}

Cluster start() {
    Cluster c;
    if (!started_by_mpirun()) return c;
    int provided = 0;
    // Only the thread that starts MPI calls it; the cells run on other threads.
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    std::atexit([] { MPI_Finalize(); });
    MPI_Comm_rank(MPI_COMM_WORLD, &c.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &c.size);
    MPI_Comm host;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, c.rank, MPI_INFO_NULL, &host);
    MPI_Comm_size(host, &c.local_size);
    MPI_Comm_free(&host);
    return c;
}

} // namespace

const Cluster& cluster() {
    static const Cluster c = start();
    return c;
}

bool built_with_mpi() { return true; }

} // namespace nesshi::paper
