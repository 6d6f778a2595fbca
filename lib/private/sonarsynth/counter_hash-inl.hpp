// SPDX-License-Identifier: MIT
// counter_hash.hpp on Highway vectors of uint32 (per target: include after hwy/highway.h in a
// file compiled through hwy/foreach_target.h). Lane i equals the scalar function of lane i.
#if defined(SONARSYNTH_COUNTER_HASH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SONARSYNTH_COUNTER_HASH_INL_H_
#undef SONARSYNTH_COUNTER_HASH_INL_H_
#else
#define SONARSYNTH_COUNTER_HASH_INL_H_
#endif

#include <hwy/highway.h>

#include "sonarsynth/counter_hash.hpp"

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::counter_hash::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class D>
HWY_INLINE hn::Vec<D> mix32(D d, hn::Vec<D> x) {
  x = hn::Xor(x, hn::ShiftRight<16>(x));
  x = hn::Mul(x, hn::Set(d, 0x21f0aaadU));
  x = hn::Xor(x, hn::ShiftRight<15>(x));
  x = hn::Mul(x, hn::Set(d, 0x735a2d97U));
  return hn::Xor(x, hn::ShiftRight<15>(x));
}

template <class D>
HWY_INLINE hn::Vec<D> key_word(D d, const Stream& s, hn::Vec<D> key_lo, hn::Vec<D> key_hi) {
  const auto a = mix32(d, hn::Xor(key_lo, hn::Set(d, s.s0)));
  return mix32(d, hn::Xor(hn::Xor(a, key_hi), hn::Set(d, s.s1)));
}

template <class D>
HWY_INLINE hn::Vec<D> draw(D d, const Stream& s, hn::Vec<D> h, std::uint32_t counter) {
  return mix32(d, hn::Xor(h, hn::Set(d, s.s2 + counter * 0x9e3779b9U)));
}

/// uniform_open per lane: (w >> 8) 2^-24 + 2^-25 as float (exact in float's 24-bit mantissa).
template <class DF, class DU>
HWY_INLINE hn::Vec<DF> uniform_open(DF df, DU, hn::Vec<DU> w) {
  const auto m = hn::ConvertTo(df, hn::BitCast(hn::RebindToSigned<DU>(), hn::ShiftRight<8>(w)));
  return hn::MulAdd(m, hn::Set(df, 0x1p-24f), hn::Set(df, 0x1p-25f));
}

}  // namespace sonarsynth::counter_hash::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // SONARSYNTH_COUNTER_HASH_INL_H_
