#include "sphdem/parallel/comm.hpp"

namespace sphdem {

Comm::Comm(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

namespace {
template <class T>
T reduce(MPI_Comm comm, T v, MPI_Datatype type, MPI_Op op) {
  T out{};
  MPI_Allreduce(&v, &out, 1, type, op, comm);
  return out;
}
}  // namespace

double Comm::max(double v) const {
  return reduce(comm_, v, MPI_DOUBLE, MPI_MAX);
}
double Comm::min(double v) const {
  return reduce(comm_, v, MPI_DOUBLE, MPI_MIN);
}
double Comm::sum(double v) const {
  return reduce(comm_, v, MPI_DOUBLE, MPI_SUM);
}
void Comm::sum(std::span<double> v) const {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, comm_);
}
void Comm::sum(std::span<std::int64_t> v) const {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_INT64_T, MPI_SUM, comm_);
}
std::int64_t Comm::sum(std::int64_t v) const {
  return reduce(comm_, v, MPI_INT64_T, MPI_SUM);
}
std::int64_t Comm::max(std::int64_t v) const {
  return reduce(comm_, v, MPI_INT64_T, MPI_MAX);
}
std::int64_t Comm::min(std::int64_t v) const {
  return reduce(comm_, v, MPI_INT64_T, MPI_MIN);
}
bool Comm::any(bool v) const {
  return reduce<int>(comm_, v ? 1 : 0, MPI_INT, MPI_MAX) != 0;
}
void Comm::barrier() const {
  MPI_Barrier(comm_);
}

int Comm::ranks_on_node() const {
  MPI_Comm node;
  MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  int n = 1;
  MPI_Comm_size(node, &n);
  MPI_Comm_free(&node);
  return n;
}

}  // namespace sphdem
