#include "sphdem/parallel/comm.hpp"

#include <algorithm>
#include <vector>

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
void Comm::any(std::span<std::uint8_t> v) const {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_UINT8_T, MPI_BOR, comm_);
}
void Comm::max(std::span<double> v) const {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_MAX, comm_);
}
namespace {
// The reduction of Comm::sum_max over records [n_sum, sums..., maxes...]
// (one record: a contiguous type of the whole buffer).
void sum_max_op(void* in, void* inout, int* len, MPI_Datatype* type) {
  int bytes = 0;
  MPI_Type_size(*type, &bytes);
  const auto n = static_cast<std::size_t>(bytes) / sizeof(double);
  const auto* a = static_cast<const double*>(in);
  auto* b = static_cast<double*>(inout);
  for (int rec = 0; rec < *len; ++rec, a += n, b += n) {
    const auto n_sum = static_cast<std::size_t>(a[0]);
    for (std::size_t k = 1; k <= n_sum; ++k) b[k] = a[k] + b[k];
    for (std::size_t k = n_sum + 1; k < n; ++k) b[k] = std::max(a[k], b[k]);
  }
}
}  // namespace

void Comm::sum_max(std::span<double> sums, std::span<double> maxes) const {
  if (size_ == 1) return;
  std::vector<double> buf;
  buf.reserve(1 + sums.size() + maxes.size());
  buf.push_back(static_cast<double>(sums.size()));
  buf.insert(buf.end(), sums.begin(), sums.end());
  buf.insert(buf.end(), maxes.begin(), maxes.end());
  static const MPI_Op op = [] {
    MPI_Op o;
    MPI_Op_create(&sum_max_op, /*commute=*/1, &o);
    return o;
  }();
  MPI_Datatype record;
  MPI_Type_contiguous(static_cast<int>(buf.size()), MPI_DOUBLE, &record);
  MPI_Type_commit(&record);
  MPI_Allreduce(MPI_IN_PLACE, buf.data(), 1, record, op, comm_);
  MPI_Type_free(&record);
  std::copy(buf.begin() + 1, buf.begin() + 1 + static_cast<std::ptrdiff_t>(sums.size()),
            sums.begin());
  std::copy(buf.begin() + 1 + static_cast<std::ptrdiff_t>(sums.size()), buf.end(), maxes.begin());
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
