#pragma once
// Lists of record fields and where each sits in a record: the pair loop's
// (pair_loop.hpp) and the passes' (pass_loop.hpp) records and lane blocks,
// and the compact record (compact_record.hpp).
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

#include "term_interface.hpp"

namespace sphdem::terms {

template <class L, class F>
struct Append;
template <class... Fs, class F>
struct Append<Fields<Fs...>, F> {
  using type = std::conditional_t<(std::is_same_v<F, Fs> || ...), Fields<Fs...>, Fields<Fs..., F>>;
};
template <class... Fs>
struct Append<Fields<Fs...>, void> {
  using type = Fields<Fs...>;
};

// L followed by the fields of M not yet in L; with kSources, a relative
// field's source (VelWall's Vel) too, since its lane reads i's source.
template <class L, class M, bool kSources>
struct Merge;
template <class L, bool kSources>
struct Merge<L, Fields<>, kSources> {
  using type = L;
};
template <class L, class F, class... Rest, bool kSources>
struct Merge<L, Fields<F, Rest...>, kSources> {
  using with_source =
      std::conditional_t<kSources, typename Append<L, typename F::RelativeTo>::type, L>;
  using type =
      typename Merge<typename Append<with_source, F>::type, Fields<Rest...>, kSources>::type;
};
template <bool kSources, class L, class... Ms>
struct MergeAll {
  using type = L;
};
template <bool kSources, class L, class M, class... Ms>
struct MergeAll<kSources, L, M, Ms...> {
  using type = typename MergeAll<kSources, typename Merge<L, M, kSources>::type, Ms...>::type;
};

// Where each field of L sits in a record (or a lane block) of D-dimensional doubles.
template <int D, class L>
struct Layout;
template <int D, class... Fs>
struct Layout<D, Fields<Fs...>> {
  static constexpr std::size_t kSize = (std::size_t{0} + ... + width_v<Fs, D>);
  template <class F>
  static constexpr std::size_t offset() {
    static_assert(contains_v<F, Fields<Fs...>>, "field not in this layout");
    std::size_t o = 0;
    bool found = false;
    ((found = found || std::is_same_v<F, Fs>, o += found ? 0 : width_v<Fs, D>), ...);
    return o;
  }
  static std::vector<std::string> names() { return {Fs::name...}; }
};

// L without the field F.
template <class G, class L>
struct Prepend;
template <class G, class... Fs>
struct Prepend<G, Fields<Fs...>> {
  using type = Fields<G, Fs...>;
};
template <class F, class L>
struct Without;
template <class F>
struct Without<F, Fields<>> {
  using type = Fields<>;
};
template <class F, class G, class... Gs>
struct Without<F, Fields<G, Gs...>> {
  using rest = typename Without<F, Fields<Gs...>>::type;
  using type = std::conditional_t<std::is_same_v<F, G>, rest, typename Prepend<G, rest>::type>;
};

}  // namespace sphdem::terms
