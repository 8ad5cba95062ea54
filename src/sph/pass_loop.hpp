#pragma once
// Neighbour-sum preparation passes: a per-particle quantity that the pair
// terms of the same rate evaluation read on their neighbours (the shear
// rate; later a normal or a curvature), so it must be complete on every
// owned particle and refreshed on the ghosts before the pair loop runs
// (docs/architecture.md, "Adding a physics term", "with a neighbour-sum
// pass"). A pass is a struct with:
//
//   static constexpr const char* name;   // the output name of its field (output.fields)
//   using Reads = Fields<...>;           // record fields read per neighbour
//   using Output = <record field>;       // its result as terms read it (Reads of a term)
//   static constexpr SphGroup group;     // the exchange group of its field
//   template <int D> static constexpr std::size_t kSums;   // accumulators per particle
//   template <int D> static std::vector<double>& output(SphParticles<D>&);
//   explicit P(const TermContext<D>&);   // optional: its parameters
//   void pair(const PairView&, double* s) const;   // s[0..kSums): this pair's part
//   template <int D> double finish(const double* sums) const;   // the particle's value
// and optionally: also_outputs (more snapshot fields it writes), needed(sp)
// (a step besides the terms needs it), store<D>(sums, ps, i) and clear<D>(ps, i)
// (more fields from the same sums, and their value on walls), and
//
//   using Lite = Q;   // a cheaper pass into the same output field
//
// run instead of P when nothing asks for P (no active term reads its Output,
// output.fields does not name it, needed(sp) is false) but Q::needed(sp) does.
// Q has P's members but name, Output and group (P's are used) and may declare
//   template <int D> static bool wanted(const SphParams&, const SphParticles<D>&, i);
// the particles whose value a reader uses; the others get 0 without their sums.
// The free-surface pass's flag for the anti-clump term alone is such a Lite
// (terms/free_surface.hpp, FreeSurfaceFlag). A pass may also declare
//
//   template <int D> static bool settled(const double* sums);
//   using SettledIfPositive = <record field>;
//
// when its result cannot change once settled(sums) holds part way through
// the list, provided that field is positive on every particle: it then
// stops there (the flag's div r: its parts are V_j |F| r^2 >= 0).
//
// The loop is the pair loop's (pair_loop.hpp): records of the declared
// fields, gathered lanes, a branch-free pair function over a chunk (pairs
// beyond the support have F = 0), then a sequential sum in the neighbour
// list's global-id order, so the result is the same bits at every rank
// count. It writes the owned resin particles (walls get 0); the solver
// forwards the group to the ghosts. A pass runs when an active term reads
// its Output or output.fields names it, and never otherwise.
#include <algorithm>
#include <cstddef>
#include <string_view>
#include <vector>

#include "pair_loop.hpp"

namespace sphdem::terms {

// A compile-time list of passes, run in this order (sph_terms.hpp).
template <class... P>
struct PassList {};

template <class T, class F>
inline constexpr bool reads_v =
    contains_v<F, typename T::Reads> || contains_v<F, typename OwnReadsOf<T>::type>;

template <class T>
bool term_on(const SphParams& sp) {
  if constexpr (OptionalTerm<T>)
    return T::active(sp);
  else
    return true;
}

// How pass P runs for a case with the terms of Terms: not at all, itself, or its Lite.
enum class PassRun { Off, Full, Lite };

template <class P, class... Ts>
PassRun pass_run(const SphParams& sp, TermList<Ts...>) {
  const auto& out = sp.output_fields;
  const auto named = [&](std::string_view n) {
    return std::find(out.begin(), out.end(), n) != out.end();
  };
  bool requested = named(P::name);
  // Optional: more snapshot fields it writes (also_outputs), a step that needs it (needed).
  if constexpr (requires { P::also_outputs; })
    for (const char* n : P::also_outputs) requested = requested || named(n);
  if constexpr (requires { P::needed(sp); }) requested = requested || P::needed(sp);
  if (requested || ((reads_v<Ts, typename P::Output> && term_on<Ts>(sp)) || ...))
    return PassRun::Full;
  if constexpr (requires { typename P::Lite; })
    if (P::Lite::needed(sp)) return PassRun::Lite;
  return PassRun::Off;
}

// Whether pass P (or its Lite) runs for a case with the terms of Terms.
template <class P, class Terms>
bool pass_needed(const SphParams& sp, Terms terms) {
  return pass_run<P>(sp, terms) != PassRun::Off;
}

// The passes that run for sp, by name, in order (for tests and logs).
template <class Terms, class... Ps>
std::vector<std::string> needed_passes(const SphParams& sp, PassList<Ps...>) {
  std::vector<std::string> names;
  ((pass_needed<Ps>(sp, Terms{}) ? void(names.emplace_back(Ps::name)) : void()), ...);
  return names;
}

// Pass P over every owned resin particle.
template <int D, class P>
void run_pass(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  using LaneFields = typename MergeAll<false, Fields<field::Pos>, typename P::Reads>::type;
  using RecordFields = typename MergeAll<true, Fields<>, LaneFields>::type;
  using Lanes = Layout<D, LaneFields>;
  using Record = Layout<D, RecordFields>;
  using View = PairView<D, Lanes, Record, typename P::Reads, Fields<>>;
  constexpr std::size_t kStride = Record::kSize;  // unpadded, as the pair loop's
  constexpr std::size_t kSums = P::template kSums<D>;

  const WendlandC2<D> kernel(sp.h);
  const TermContext<D> ctx{sp, kernel, kernel.w(0.0) / 16.0};
  const P pass = make_term<P>(ctx);

  thread_local std::vector<PackedRecord<kStride>> records;
  const std::size_t n = ps.size();
  // One record more than the particles: the doubles after the last record
  // that the gather reads (kRecordSpare, lane_gather.hpp).
  static_assert(kRecordSpare<D, kStride> <= kStride);
  resize_field(records, n + 1);  // a small margin, not a doubling
  PackedRecord<kStride>* rec = records.data();
  for (std::size_t i = 0; i < n; ++i)
    FillRecord<D, RecordFields>::template run<Record>(sp, ps, i, rec[i].v);

  const double support2 = 4.0 * sp.h * sp.h;
  const double inv_h = 1.0 / sp.h;
  const double kF = -10.0 * ctx.kw * inv_h * inv_h * sp.grad_scale;  // as pair_loop.hpp
  // Optional: a pass whose result is settled part way (P::settled) takes
  // its neighbours in blocks of 16 and stops once it is, provided the
  // records' field P::SettledIfPositive is positive everywhere (what makes
  // every later part non-negative). Otherwise whole chunks, every pair.
  std::size_t block = kChunk;
  if constexpr (requires { typename P::SettledIfPositive; }) {
    constexpr std::size_t o = Record::template offset<typename P::SettledIfPositive>();
    bool positive = true;
    for (std::size_t i = 0; i < n; ++i) positive = positive && rec[i].v[o] > 0.0;
    if (positive) block = 16;
  }
  constexpr std::size_t kPos = Lanes::template offset<field::Pos>();
  alignas(64) double lanes[Lanes::kSize * kChunk];
  alignas(64) double part[kSums][kChunk];
  std::vector<double>& out = P::output(ps);

  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    bool skip = ps.kind[i] != Kind::Fluid;
    // Optional: only the particles whose value is read (a Lite's wanted).
    if constexpr (requires { P::template wanted<D>(sp, ps, i); })
      skip = skip || !P::template wanted<D>(sp, ps, i);
    if (skip) {
      out[i] = 0.0;
      if constexpr (requires { pass.template clear<D>(ps, i); }) pass.template clear<D>(ps, i);
      continue;
    }
    const double* own = rec[i].v;
    double sums[kSums] = {};
    const NeighborRow nb = nl.row(i);
    for (std::size_t b = nl.begin(i), e = nl.end(i); b < e; b += block) {
      const std::size_t cnt = std::min(block, e - b);
      // As the pair loop's step 1 (pair_loop.hpp): the indices padded with
      // the last one to a whole block of the widest gather.
      alignas(64) std::int32_t idx[kChunk + 3];
      for (std::size_t k = 0; k < cnt; ++k) idx[k] = nb[b + k];
      idx[cnt] = idx[cnt + 1] = idx[cnt + 2] = nb[b + cnt - 1];  // cnt >= 1
      GatherLanes<D, LaneFields>::template chunk<Lanes, Record>(own, rec, idx, cnt, lanes);
      for (std::size_t k = 0; k < cnt; ++k) {
        double r2 = 0.0;
        for (int d = 0; d < D; ++d) {
          const double x = lanes[(kPos + d) * kChunk + k];
          r2 += x * x;
        }
        const bool inside = r2 < support2;
        const double r = std::sqrt(r2);
        const double q = r * inv_h;
        const double t = inside ? 2.0 - q : 0.0;
        // WendlandC2::f (kernel.hpp) with the lattice correction, as in the pair loop.
        const double F = kF * (t * t) * t;
        double s[kSums];
        pass.pair(View{lanes, k, own, r2, r, q, t, F}, s);
        for (std::size_t m = 0; m < kSums; ++m) part[m][k] = s[m];
      }
      // In list (global-id) order.
      for (std::size_t k = 0; k < cnt; ++k)
        for (std::size_t m = 0; m < kSums; ++m) sums[m] += part[m][k];
      if constexpr (requires { P::template settled<D>(sums); })
        if (block < kChunk && P::template settled<D>(sums)) break;
    }
    out[i] = pass.template finish<D>(sums);
    // Optional: more fields from the same sums (store).
    if constexpr (requires { pass.template store<D>(sums, ps, i); })
      pass.template store<D>(sums, ps, i);
  }
}

// The passes of Passes that sp needs, in order (each itself or its Lite),
// each followed by forward(its group). With lites_on_the_side, a pass that
// would run as its Lite does not: the caller's pair loop computes it
// (PairLoopRun::side) and forwards it.
template <int D, class Terms, class Forward, class... Ps>
void run_passes(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                const Forward& forward, PassList<Ps...>, bool lites_on_the_side = false) {
  const auto one = [&]<class P>(P*) {
    const PassRun how = pass_run<P>(sp, Terms{});
    if (how == PassRun::Off || (how == PassRun::Lite && lites_on_the_side)) return;
    if constexpr (requires { typename P::Lite; }) {
      if (how == PassRun::Lite)
        run_pass<D, typename P::Lite>(sp, nl, ps);
      else
        run_pass<D, P>(sp, nl, ps);
    } else {
      run_pass<D, P>(sp, nl, ps);
    }
    forward(P::group);
  };
  (one(static_cast<Ps*>(nullptr)), ...);
}

}  // namespace sphdem::terms
