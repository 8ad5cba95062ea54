// The pair loop's gather (src/sph/lane_gather.hpp): four neighbours at a
// time (AVX) and eight at a time (AVX-512), by transposes in registers,
// give bit for bit the lanes of the element-by-element gather, for the
// channel's record (12 doubles, 2D), a 3D record and records of odd size,
// at every chunk length's last block; and GatherLanes::chunk, the pair
// loop's step 1, reads no double past the records' spare ones.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "../src/sph/pair_loop.hpp"
#include "../src/sph/sph_terms.hpp"

namespace sphdem {
namespace {

using namespace terms;

// What the channel with the shipped physics selects.
using Shipped = TermList<Selected<Continuity, 0>, Selected<DeltaSph, 0>, Selected<Pressure, 0>,
                         Selected<AntiClump, 0>, Selected<MorrisViscosity, 0>>;
using ContinuityOnly = TermList<Selected<Continuity, 0>>;

// Lanes of the chunk of neighbours nb[0..cnt), element by element and four
// at a time; both must agree for k < cnt (the rows beyond are not read).
// How a test gathers the chunk: the pair loop's way (GatherLanes::chunk,
// the widest this build has), or four or eight at a time throughout.
enum class Way { Loop, Four, Eight };

template <int D, class Sel>
void expect_same_lanes(std::size_t cnt, Way way = Way::Loop) {
  using N = Needs<D, Sel>;
  using Lanes = typename N::Lanes;
  using Record = typename N::Record;
  using Gather = GatherLanes<D, typename N::LaneFields>;
  constexpr std::size_t kStride = N::kStride;
  const std::size_t n = 50;
  // Exactly as many doubles as rates_loop takes (the spare doubles after
  // the last record that the widest gather reads), so a read past them is a
  // heap overflow that the sanitize preset reports. Four or eight at a time
  // throughout need their own spare.
  const std::size_t spare = way == Way::Loop   ? kRecordSpare<D, kStride>
                            : way == Way::Four ? kStride % 2
                                               : (4 - kStride % 4) % 4;
  std::vector<double> buffer(n * kStride + spare);
  const auto* rec = reinterpret_cast<const PackedRecord<kStride>*>(buffer.data());
  std::mt19937 gen(static_cast<unsigned>(cnt * 7 + kStride));
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (double& v : buffer) v = u(gen);
  std::vector<std::int32_t> nb(cnt + 7);
  std::uniform_int_distribution<std::int32_t> pick(0, static_cast<std::int32_t>(n - 1));
  for (auto& j : nb) j = pick(gen);
  nb[cnt - 1] = static_cast<std::int32_t>(n - 1);  // the last record, read to its end
  // Padded as the loop pads (three are enough for its gather; eight at a
  // time throughout reads seven).
  for (std::size_t k = cnt; k < cnt + 7; ++k) nb[k] = nb[cnt - 1];
  const double* own = rec[3].v;

  alignas(64) double one[Lanes::kSize * kChunk];
  alignas(64) double wide[Lanes::kSize * kChunk];
  std::memset(one, 0, sizeof one);
  std::memset(wide, 0, sizeof wide);
  for (std::size_t k = 0; k < cnt; ++k)
    Gather::template run<Lanes, Record>(own, rec[nb[k]], k, one);
  // tests/unit.cmake builds this file with AVX in every preset; a CPU
  // without what a way needs skips (ctest then reports the test as skipped).
  if (way == Way::Loop) {
    if (kGatherWidth<D> >= 4 && !__builtin_cpu_supports("avx")) GTEST_SKIP() << "no AVX";
    if (kGatherWidth<D> == 8 && !__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "no AVX-512";
    Gather::template chunk<Lanes, Record>(own, rec, nb.data(), cnt, wide);
  } else if (way == Way::Four) {
#if defined(__AVX__)
    if (!__builtin_cpu_supports("avx")) GTEST_SKIP() << "this CPU has no AVX";
    for (std::size_t k = 0; k < cnt; k += 4) {
      const double* const r[4] = {rec[nb[k]].v, rec[nb[k + 1]].v, rec[nb[k + 2]].v,
                                  rec[nb[k + 3]].v};
      Gather::template four_pairs<Lanes, Record>(own, r, k, wide);
    }
#else
    GTEST_SKIP() << "no AVX in this build";
#endif
  } else {
#if defined(__AVX512F__)
    if (!__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "this CPU has no AVX-512";
    for (std::size_t k = 0; k < cnt; k += 8) {
      const double* const r[8] = {rec[nb[k]].v,     rec[nb[k + 1]].v, rec[nb[k + 2]].v,
                                  rec[nb[k + 3]].v, rec[nb[k + 4]].v, rec[nb[k + 5]].v,
                                  rec[nb[k + 6]].v, rec[nb[k + 7]].v};
      Gather::template eight_quads<Lanes, Record>(own, r, k, wide);
    }
#else
    GTEST_SKIP() << "no AVX-512 in this build";
#endif
  }
  for (std::size_t row = 0; row < Lanes::kSize; ++row)
    for (std::size_t k = 0; k < cnt; ++k)
      ASSERT_EQ(std::memcmp(&one[row * kChunk + k], &wide[row * kChunk + k], sizeof(double)), 0)
          << "row " << row << " pair " << k << " of " << cnt;
}

TEST(LaneGather, FourAtATimeEqualsOneAtATimeOnTheChannelRecord) {
  static_assert(Needs<2, Shipped>::kStride == 12, "the channel's record is 12 doubles");
  for (std::size_t cnt : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 19u, 63u, 64u})
    expect_same_lanes<2, Shipped>(cnt, Way::Four);
}

TEST(LaneGather, FourAtATimeEqualsOneAtATimeIn3D) {
  for (std::size_t cnt : {1u, 6u, 33u, 64u}) expect_same_lanes<3, Shipped>(cnt, Way::Four);
}

TEST(LaneGather, FourAtATimeEqualsOneAtATimeOnARecordOfOddSize) {
  static_assert(Needs<3, ContinuityOnly>::kStride % 2 == 1, "x, v, m in 3D: 7 doubles");
  for (std::size_t cnt : {1u, 3u, 4u, 21u, 64u})
    expect_same_lanes<3, ContinuityOnly>(cnt, Way::Four);
}

// Eight at a time reads quads: records of 7 (3 spare doubles), 12 (none)
// and 15 doubles (1 spare: x, v, vwall, m and the shipped scalars in 3D).
TEST(LaneGather, EightAtATimeEqualsOneAtATime) {
  static_assert(Needs<3, Shipped>::kStride == 15, "the 3D shipped record is 15 doubles");
  for (std::size_t cnt : {1u, 4u, 5u, 8u, 9u, 13u, 61u, 64u}) {
    expect_same_lanes<3, ContinuityOnly>(cnt, Way::Eight);
    expect_same_lanes<2, Shipped>(cnt, Way::Eight);
    expect_same_lanes<3, Shipped>(cnt, Way::Eight);
  }
}

// The pair loop's own gather (eight at a time in 3D with AVX-512, the last
// block of at most four four at a time), with exactly the loop's spare.
TEST(LaneGather, ThePairLoopsGatherEqualsOneAtATime) {
  for (std::size_t cnt : {1u, 3u, 4u, 5u, 12u, 20u, 21u, 60u, 64u}) {
    expect_same_lanes<2, Shipped>(cnt);
    expect_same_lanes<3, Shipped>(cnt);
    expect_same_lanes<3, ContinuityOnly>(cnt);
  }
}

}  // namespace
}  // namespace sphdem
