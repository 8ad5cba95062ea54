// The pair loop's gather (src/sph/lane_gather.hpp): four neighbours at a
// time by a transpose in registers gives bit for bit the lanes of the
// element-by-element gather, for the channel's record (12 doubles, 2D), a 3D
// record and a record of odd size, at every chunk length's last block.
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
template <int D, class Sel>
void expect_same_lanes(std::size_t cnt) {
  using N = Needs<D, Sel>;
  using Lanes = typename N::Lanes;
  using Record = typename N::Record;
  using Gather = GatherLanes<D, typename N::LaneFields>;
  constexpr std::size_t kStride = N::kStride;
  const std::size_t n = 50;
  // Exactly as many doubles as rates_loop takes (one spare double after an
  // odd-sized last record), so a read past them is a heap overflow that
  // the sanitize preset reports.
  std::vector<double> buffer(n * kStride + kStride % 2);
  const auto* rec = reinterpret_cast<const PackedRecord<kStride>*>(buffer.data());
  std::mt19937 gen(static_cast<unsigned>(cnt * 7 + kStride));
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (double& v : buffer) v = u(gen);
  std::vector<std::int32_t> nb(cnt);
  std::uniform_int_distribution<std::int32_t> pick(0, static_cast<std::int32_t>(n - 1));
  for (auto& j : nb) j = pick(gen);
  nb[cnt - 1] = static_cast<std::int32_t>(n - 1);  // the last record, read to its end
  const double* own = rec[3].v;

  alignas(64) double one[Lanes::kSize * kChunk];
  alignas(64) double four[Lanes::kSize * kChunk];
  std::memset(one, 0, sizeof one);
  std::memset(four, 0, sizeof four);
  for (std::size_t k = 0; k < cnt; ++k)
    Gather::template run<Lanes, Record>(own, rec[nb[k]], k, one);
#if defined(__AVX__)
  // tests/unit.cmake builds this file with AVX in every preset; a CPU
  // without it skips (ctest then reports the test as skipped).
  if (!__builtin_cpu_supports("avx")) GTEST_SKIP() << "this CPU has no AVX";
  for (std::size_t k = 0; k < cnt; k += 4) {
    const double* const r[4] = {rec[nb[k]].v, rec[nb[std::min(k + 1, cnt - 1)]].v,
                                rec[nb[std::min(k + 2, cnt - 1)]].v,
                                rec[nb[std::min(k + 3, cnt - 1)]].v};
    Gather::template four_pairs<Lanes, Record>(own, r, k, four);
  }
#else
  GTEST_SKIP() << "no AVX: the pair loop gathers element by element only";
#endif
  for (std::size_t row = 0; row < Lanes::kSize; ++row)
    for (std::size_t k = 0; k < cnt; ++k)
      ASSERT_EQ(std::memcmp(&one[row * kChunk + k], &four[row * kChunk + k], sizeof(double)), 0)
          << "row " << row << " pair " << k << " of " << cnt;
}

TEST(LaneGather, FourAtATimeEqualsOneAtATimeOnTheChannelRecord) {
  static_assert(Needs<2, Shipped>::kStride == 12, "the channel's record is 12 doubles");
  for (std::size_t cnt : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 19u, 63u, 64u})
    expect_same_lanes<2, Shipped>(cnt);
}

TEST(LaneGather, FourAtATimeEqualsOneAtATimeIn3D) {
  for (std::size_t cnt : {1u, 6u, 33u, 64u}) expect_same_lanes<3, Shipped>(cnt);
}

TEST(LaneGather, FourAtATimeEqualsOneAtATimeOnARecordOfOddSize) {
  static_assert(Needs<3, ContinuityOnly>::kStride % 2 == 1, "x, v, m in 3D: 7 doubles");
  for (std::size_t cnt : {1u, 3u, 4u, 21u, 64u}) expect_same_lanes<3, ContinuityOnly>(cnt);
}

}  // namespace
}  // namespace sphdem
