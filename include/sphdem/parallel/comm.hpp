#pragma once
// The only door to MPI for the rest of the code (parallel/ and io/ use
// raw()). Physics modules never include this header.
#include <mpi.h>

#include <cstdint>
#include <span>

namespace sphdem {

class Comm {
 public:
  explicit Comm(MPI_Comm comm = MPI_COMM_WORLD);
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  MPI_Comm raw() const { return comm_; }

  double max(double v) const;
  double min(double v) const;
  double sum(double v) const;
  std::int64_t sum(std::int64_t v) const;
  void sum(std::span<double> v) const;  // element-wise, in place: one allreduce
  void sum(std::span<std::int64_t> v) const;
  void max(std::span<double> v) const;  // element-wise, in place: one allreduce
  // Element-wise, in place, in one allreduce: `sums` summed, `maxes` the
  // largest (a minimum travels as the largest negation, exact).
  void sum_max(std::span<double> sums, std::span<double> maxes) const;
  std::int64_t max(std::int64_t v) const;
  std::int64_t min(std::int64_t v) const;
  bool any(bool v) const;
  void any(std::span<std::uint8_t> v) const;  // element-wise or of 0/1 flags, in place
  void barrier() const;
  // Collective: how many ranks of this communicator share this rank's node
  // (its memory): MPI_Comm_split_type with MPI_COMM_TYPE_SHARED.
  int ranks_on_node() const;

 private:
  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace sphdem
