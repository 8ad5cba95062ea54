#pragma once
// The fibers as they are now, per owned DEM particle, without any rank
// holding every particle or bond (docs/checkpoint.md, "At scale"): the
// piece it is in (the smallest gid of its connected piece of intact bonds,
// and the piece's length, include/sphdem/dem/fiber_pieces.hpp) and its
// fiber's unit end-to-end direction.
//
// Each placed fiber has a home rank (fiber ids are dense: the home of fiber
// f is f * P / n_fibers, so each home has about n_fibers / P fibers, i.e.
// N / P particles, wherever they are in the mold). Every rank sends its
// owned particles (gid, fiber, radius), their intact bonds and their bond
// vectors to the homes of their fibers; each home finds the pieces of its
// fibers with the serial union-find and sums their directions, and answers
// each particle. Bonds only join particles of one placed fiber (the
// generator bonds consecutive particles of a fiber, src/dem/fiber_generator.cpp),
// so a home holds every particle and bond its pieces need; a bond to a
// particle the home does not hold is a broken invariant (std::logic_error).
//
// Bitwise the same as the gathered computation: a piece's length is summed
// over its particles in increasing gid (fiber_pieces), a fiber's direction
// over its bond vectors in increasing bond id (as ordered_sums does), and
// both sets lie in one home.
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphdem/dem/fiber_pieces.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/record_route.hpp"
#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {

template <int D>
struct OwnedFiberState {
  // Per owned particle: piece id (-1 for a loose particle), piece length [m],
  // its fiber's unit direction (zero for a loose particle).
  std::vector<std::int64_t> piece;
  std::vector<double> length;
  std::vector<Vec<D>> direction;
};

namespace fiber_homes_detail {

struct ParticleRecord {
  std::int64_t gid;
  std::int64_t fiber;
  double radius;
};
struct BondRecord {
  std::int64_t owner, partner, fiber;
};
struct DirectionTerm {
  std::int64_t bond;  // the sum's order: bond id
  std::int64_t fiber;
  double d[3];
};
struct Answer {
  std::int64_t piece;
  double length;
  double direction[3];
};

// The fibers' dense ids [0, n) split in P contiguous ranges.
inline int home_of(std::int64_t fiber, std::int64_t n_fibers, int ranks) {
  return static_cast<int>(fiber * ranks / n_fibers);
}

// Unit vector, its first nonzero component positive (a fiber has no head).
template <int D>
Vec<D> unit_headless(Vec<D> d) {
  const double n = d.norm();
  d = n > 0 ? Vec<D>(d / n) : Vec<D>::Zero();
  for (int k = 0; k < D; ++k) {
    if (d[k] == 0) continue;
    if (d[k] < 0) d = -d;
    break;
  }
  return d;
}

}  // namespace fiber_homes_detail

// Collective. The ghosts must hold the bond partners within the halo (a
// partner beyond it adds no term to the direction, as before).
template <int D>
OwnedFiberState<D> owned_fiber_state(const DemParticles<D>& ps, const Comm& comm) {
  using namespace fiber_homes_detail;
  std::int64_t n_fibers = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    n_fibers = std::max<std::int64_t>(n_fibers, ps.fiber[i] + 1);
  n_fibers = comm.max(n_fibers);
  const int p = comm.size();

  // What this rank sends: its owned fiber particles, their intact bonds,
  // their bond vectors (partner positions from the ghosts).
  std::vector<std::pair<std::int64_t, std::size_t>> index;  // gid -> local, owned and ghosts
  for (std::size_t i = 0; i < ps.size(); ++i) index.emplace_back(ps.gid[i], i);
  std::sort(index.begin(), index.end());
  std::vector<ParticleRecord> particles;
  std::vector<BondRecord> bonds;
  std::vector<DirectionTerm> terms;
  std::vector<int> particle_home, bond_home, term_home;
  std::vector<std::size_t> asked;  // owned index of each particle record
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const std::int64_t f = ps.fiber[i];
    if (f < 0) {
      for (const DemBond<D>& b : ps.bonds[i])
        if (b.partner >= 0 && !b.broken)
          throw std::logic_error("sphdem: a loose DEM particle (" + std::to_string(ps.gid[i]) +
                                 ") has an intact bond");
      continue;
    }
    const int home = home_of(f, n_fibers, p);
    particles.push_back({ps.gid[i], f, ps.radius[i]});
    particle_home.push_back(home);
    asked.push_back(i);
    for (const DemBond<D>& b : ps.bonds[i]) {
      if (b.partner < 0) continue;
      if (!b.broken) {
        bonds.push_back({ps.gid[i], b.partner, f});
        bond_home.push_back(home);
      }
      const auto it =
          std::lower_bound(index.begin(), index.end(), std::make_pair(b.partner, std::size_t{0}));
      if (it == index.end() || it->first != b.partner) continue;  // beyond the halo
      const Vec<D> d = ps.x[it->second] - ps.x[i];
      DirectionTerm t{b.id, f, {0, 0, 0}};
      for (int k = 0; k < D; ++k) t.d[k] = d[k];
      terms.push_back(t);
      term_home.push_back(home);
    }
  }
  const RecordRoute to_particles = route_records(comm, particles, particle_home);
  const RecordRoute to_bonds = route_records(comm, bonds, bond_home);
  const RecordRoute to_terms = route_records(comm, terms, term_home);

  // At the home: its fibers' particles, pieces and directions.
  const std::vector<ParticleRecord> mine = received_records<ParticleRecord>(to_particles);
  FiberPieceInput in;
  for (const ParticleRecord& r : mine) {
    in.gid.push_back(r.gid);
    in.fiber.push_back(static_cast<std::int32_t>(r.fiber));
    in.radius.push_back(r.radius);
  }
  std::vector<std::pair<std::int64_t, std::int64_t>> fiber_of;  // gid -> fiber, sorted
  for (const ParticleRecord& r : mine) fiber_of.emplace_back(r.gid, r.fiber);
  std::sort(fiber_of.begin(), fiber_of.end());
  for (const BondRecord& b : received_records<BondRecord>(to_bonds)) {
    const auto it = std::lower_bound(fiber_of.begin(), fiber_of.end(),
                                     std::make_pair(b.partner, std::int64_t{-1}));
    if (it == fiber_of.end() || it->first != b.partner || it->second != b.fiber)
      throw std::logic_error("sphdem: the bond of DEM particles " + std::to_string(b.owner) +
                             " and " + std::to_string(b.partner) +
                             " joins two fibers (fiber pieces assume it never does)");
    in.bonds.emplace_back(b.owner, b.partner);
  }
  const FiberPieces pieces = fiber_pieces(in);

  std::vector<DirectionTerm> received = received_records<DirectionTerm>(to_terms);
  std::sort(received.begin(), received.end(), [](const DirectionTerm& a, const DirectionTerm& b) {
    return a.bond != b.bond ? a.bond < b.bond : a.fiber < b.fiber;
  });
  const std::int64_t first_fiber = (n_fibers * comm.rank() + p - 1) / p;  // smallest f homed here
  const std::int64_t end_fiber = (n_fibers * (comm.rank() + 1) + p - 1) / p;
  std::vector<Vec<D>> sums(
      static_cast<std::size_t>(std::max<std::int64_t>(0, end_fiber - first_fiber)), Vec<D>::Zero());
  for (const DirectionTerm& t : received) {
    if (t.fiber < first_fiber || t.fiber >= end_fiber)
      throw std::logic_error("sphdem: a fiber's direction term reached the wrong home");
    Vec<D>& s = sums[static_cast<std::size_t>(t.fiber - first_fiber)];
    for (int k = 0; k < D; ++k) s[k] += t.d[k];
  }
  std::vector<Answer> answers(mine.size());
  for (std::size_t r = 0; r < mine.size(); ++r) {
    const Vec<D> dir =
        unit_headless<D>(sums[static_cast<std::size_t>(mine[r].fiber - first_fiber)]);
    answers[r] = {pieces.piece[r], pieces.length[r], {0, 0, 0}};
    for (int k = 0; k < D; ++k) answers[r].direction[k] = dir[k];
  }
  const std::vector<Answer> back = reply_records(to_particles, answers);

  OwnedFiberState<D> out;
  out.piece.assign(ps.n_owned, -1);
  out.length.assign(ps.n_owned, 0.0);
  out.direction.assign(ps.n_owned, Vec<D>::Zero());
  for (std::size_t r = 0; r < asked.size(); ++r) {
    const std::size_t i = asked[r];
    out.piece[i] = back[r].piece;
    out.length[i] = back[r].length;
    for (int k = 0; k < D; ++k) out.direction[i][k] = back[r].direction[k];
  }
  return out;
}

}  // namespace sphdem
