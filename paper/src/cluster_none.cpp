// The cluster of a build without MPI: always this one process, so the cell engine never hands
// cells to another (transport::serve and transport::work are never called).
#include "paper/cluster.hpp"

#include "cell_transport.hpp"

#include <stdexcept>

namespace nesshi::paper {

const Cluster& cluster() {
    static const Cluster c;
    return c;
}

bool built_with_mpi() { return false; }

namespace transport {

void serve(const std::function<std::optional<std::size_t>()>&,
           const std::function<void(std::size_t, bool, std::string, double)>&) {
    throw std::logic_error("transport::serve in a build without MPI");
}

void work(int, const std::function<std::string(std::size_t)>&) {
    throw std::logic_error("transport::work in a build without MPI");
}

} // namespace transport

} // namespace nesshi::paper
