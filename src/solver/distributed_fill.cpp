// fill_distributed (distributed_fill.hpp). Three passes over the lattice,
// each rank over 1/P of it:
// 1. count: rank r classifies the rows q = r mod P; per top-level cell it
//    counts the resin and wall nodes (the partition weighs them), per row
//    too, and it cuts each row into segments, one per top-level cell;
// 2. the row counts are summed over ranks and scanned in row order, which
//    gives every segment the id of its first resin and first wall particle
//    (ids as on one rank: resin in lattice order, then walls);
// 3. after the partition each segment goes to the owner of its cell, which
//    classifies its nodes again and fills them.
// Per rank: O(N/P) nodes classified twice, the per-row counts (one line of
// the lattice per row: N^((D-1)/D) rows) and the per-cell work the
// partition already sums.
#include "distributed_fill.hpp"

#include <algorithm>
#include <array>
#include <exception>
#include <limits>
#include <optional>
#include <span>
#include <string>

#include <fmt/format.h>

#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/lattice_fill.hpp"
#include "sphdem/parallel/agreement.hpp"
#include "sphdem/parallel/records.hpp"

namespace sphdem {

namespace {

// One row segment: the nodes [i0, i1] of row q that lie in one top-level
// cell, with the resin and wall nodes before it in its row and in it.
struct Segment {
  std::int64_t q, i0, i1, block, fluid_before, wall_before, fluid, wall;
};
// What the owner receives: the range and its first ids and counts.
constexpr std::size_t kRecordWidth = 7;  // q, i0, i1, first resin id, first wall id, resin, walls

// Runs `f` on every rank; if it throws on any, every rank throws the
// lowest failing rank's error (an InputError keeps its text).
template <class F>
void agree_on_input_errors(const Comm& comm, const Case& c, F&& f) {
  std::optional<std::string> error;
  std::exception_ptr mine;
  try {
    f();
  } catch (const std::exception& e) {
    error = e.what();
    mine = std::current_exception();
  }
  const std::optional<RankFailure> failed = first_failure(comm, error);
  if (!failed) return;
  if (failed->rank == comm.rank()) std::rethrow_exception(mine);
  throw InputError(c.source_file, 0, "",
                   fmt::format("on rank {}: {}", failed->rank, failed->message));
}

}  // namespace

template <int D>
InitialCounts fill_distributed(const Case& c, Decomposition<D>& dec, SphParticles<D>& out) {
  const Comm& comm = dec.comm();
  const LatticeFill<D> lattice(c);
  const std::int64_t rows = lattice.rows();
  const auto ranks = static_cast<std::int64_t>(comm.size());

  // 1. Count this rank's rows.
  // Resin and wall nodes per top-level cell, weighed in step 3 (a wall's
  // weight depends on the resin near it, on any rank: Decomposition::weigh).
  std::vector<std::int64_t> fluid_in(static_cast<std::size_t>(dec.blocks()), 0);
  std::vector<std::int64_t> walls_in(fluid_in.size(), 0);
  std::vector<std::int64_t> hits(lattice.fill_shapes() + 1, 0);                 // + empty cavity
  std::vector<std::int64_t> row_counts(2 * static_cast<std::size_t>(rows), 0);  // resin, walls
  std::vector<Segment> segments;
  for (std::int64_t q = comm.rank(); q < rows; q += ranks) {
    std::int64_t fluid = 0, wall = 0;
    for (long i = lattice.x_first(); i <= lattice.x_last(); ++i) {
      const Vec<D> p = lattice.node(q, i);
      const NodeClass cls = lattice.classify(p);
      if (cls.empty_cavity()) ++hits.back();
      if (cls.none()) continue;
      const long b = dec.block_of(p);
      if (segments.empty() || segments.back().q != q || segments.back().block != b)
        segments.push_back(Segment{q, i, i, b, fluid, wall, 0, 0});
      Segment& s = segments.back();
      s.i1 = i;
      if (cls.fluid()) {
        ++fluid;
        ++s.fluid;
        ++hits[static_cast<std::size_t>(cls.value)];
        ++fluid_in[static_cast<std::size_t>(b)];
      } else {
        ++wall;
        ++s.wall;
        ++walls_in[static_cast<std::size_t>(b)];
      }
    }
    row_counts[2 * static_cast<std::size_t>(q)] = fluid;
    row_counts[2 * static_cast<std::size_t>(q) + 1] = wall;
  }

  // 2. Global counts (integers: the same sums at every rank count).
  comm.sum(std::span<std::int64_t>(hits));
  lattice.check_fill_hits(hits);  // the same sums everywhere: every rank throws
  comm.sum(std::span<std::int64_t>(row_counts));
  std::int64_t n_fluid = 0, n_wall = 0;
  for (std::int64_t q = 0; q < rows; ++q) {  // exclusive scan, in place
    std::int64_t& f = row_counts[2 * static_cast<std::size_t>(q)];
    std::int64_t& w = row_counts[2 * static_cast<std::size_t>(q) + 1];
    const std::int64_t nf = f, nw = w;
    f = n_fluid;
    w = n_wall;
    n_fluid += nf;
    n_wall += nw;
  }

  // 3. Partition by the work, then send each segment to its owner.
  dec.partition(dec.weigh(fluid_in, walls_in), /*replicated=*/false);
  fluid_in = {};
  walls_in = {};
  std::vector<int> dest;
  std::vector<std::int64_t> records;
  dest.reserve(segments.size());
  records.reserve(segments.size() * kRecordWidth);
  for (const Segment& s : segments) {
    dest.push_back(dec.block_owners()[static_cast<std::size_t>(s.block)]);
    const auto row = 2 * static_cast<std::size_t>(s.q);
    records.insert(records.end(), {s.q, s.i0, s.i1, row_counts[row] + s.fluid_before,
                                   n_fluid + row_counts[row + 1] + s.wall_before, s.fluid, s.wall});
  }
  segments = {};
  row_counts = {};
  std::vector<std::int64_t> mine = route_records(comm, dest, records, kRecordWidth);
  records = {};
  const std::size_t n_mine = mine.size() / kRecordWidth;
  // In lattice order, so each kind's ids ascend as on one rank.
  std::vector<std::size_t> order(n_mine);
  for (std::size_t k = 0; k < n_mine; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&mine](std::size_t a, std::size_t b) {
    return std::array{mine[a * kRecordWidth], mine[a * kRecordWidth + 1]} <
           std::array{mine[b * kRecordWidth], mine[b * kRecordWidth + 1]};
  });
  std::size_t own_fluid = 0, own_wall = 0;
  for (std::size_t k = 0; k < n_mine; ++k) {
    own_fluid += static_cast<std::size_t>(mine[k * kRecordWidth + 5]);
    own_wall += static_cast<std::size_t>(mine[k * kRecordWidth + 6]);
  }
  // Exactly this rank's share: no growth slack.
  out.for_each_field(
      [n = own_fluid + own_wall](const char*, auto& field, FieldPolicy) { field.reserve(n); });

  std::vector<std::size_t> fill_of;
  fill_of.reserve(own_fluid);
  double top = -std::numeric_limits<double>::infinity();
  agree_on_input_errors(comm, c, [&] {
    for (const bool resin : {true, false}) {  // resin first, then walls
      for (std::size_t k : order) {
        const std::int64_t* r = &mine[k * kRecordWidth];
        std::int64_t id = resin ? r[3] : r[4];
        for (long i = static_cast<long>(r[1]); i <= static_cast<long>(r[2]); ++i) {
          const Vec<D> p = lattice.node(r[0], i);
          const NodeClass cls = lattice.classify(p);
          if (cls.none() || cls.fluid() != resin) continue;
          lattice.push(out, id++, p, cls, fill_of);
          if (resin) top = std::max(top, lattice.height(p));
        }
      }
    }
    if (out.n_owned != own_fluid + own_wall)
      throw std::logic_error(
          "sphdem: the distributed set-up filled another count than it "
          "counted");
  });
  mine = {};
  top = comm.max(top);
  agree_on_input_errors(comm, c, [&] { lattice.finish(out, fill_of, top); });
  return InitialCounts{static_cast<std::size_t>(n_fluid), static_cast<std::size_t>(n_wall)};
}

template InitialCounts fill_distributed<2>(const Case&, Decomposition<2>&, SphParticles<2>&);
template InitialCounts fill_distributed<3>(const Case&, Decomposition<3>&, SphParticles<3>&);

}  // namespace sphdem
