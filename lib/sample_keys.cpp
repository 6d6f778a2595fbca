// SPDX-License-Identifier: MIT
// The speckle keys of a ping side in vector form (sample_keys.hpp): 64-bit lanes, compiled per
// Highway target (AVX-512, AVX2, EMU128) and dispatched at run time. Every lane gives the scalar
// functions' value bit for bit: the cell indices are floors of the same products (this file is
// compiled without floating-point contraction), packed through the exact 1.5 2^52 + floor trick.
#include "sonarsynth/sample_keys.hpp"

#include "sonarsynth/simd.hpp"

// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lib/sample_keys.cpp"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace sonarsynth::sample_keys::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// a c mod 2^64 per lane: AVX2 has no 64-bit lane multiply, it takes 32 x 32 -> 64 products,
// a_lo c_lo + ((a_hi c_lo + a_lo c_hi) << 32); the other targets multiply 64-bit lanes.
template <class D>
HWY_INLINE hn::Vec<D> mul64(D d, hn::Vec<D> a, std::uint64_t c) {
#if HWY_TARGET != HWY_AVX2
  return hn::Mul(a, hn::Set(d, c));
#else
  const hn::Repartition<std::uint32_t, D> d32;
  const auto c_lo = hn::BitCast(d32, hn::Set(d, c & 0xffffffffULL));
  const auto c_hi = hn::BitCast(d32, hn::Set(d, c >> 32));
  const auto a32 = hn::BitCast(d32, a);
  const auto lo = hn::MulEven(a32, c_lo);
  const auto cross =
      hn::Add(hn::MulEven(hn::BitCast(d32, hn::ShiftRight<32>(a)), c_lo), hn::MulEven(a32, c_hi));
  return hn::Add(lo, hn::ShiftLeft<32>(cross));
#endif
}

template <class D>
HWY_INLINE hn::Vec<D> splitmix64(D d, hn::Vec<D> x) {
  x = hn::Add(x, hn::Set(d, 0x9e3779b97f4a7c15ULL));
  x = mul64(d, hn::Xor(x, hn::ShiftRight<30>(x)), 0xbf58476d1ce4e5b9ULL);
  x = mul64(d, hn::Xor(x, hn::ShiftRight<27>(x)), 0x94d049bb133111ebULL);
  return hn::Xor(x, hn::ShiftRight<31>(x));
}

void ping_keys(std::uint64_t h, const std::uint64_t* sample_hash, std::size_t n,
               std::uint64_t* keys) {
#if HWY_TARGET == HWY_SCALAR || HWY_TARGET == HWY_EMU128
  // The portable targets: the scalar loop.
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = kPingSampleKeyBit | (sonarsynth::splitmix64(h ^ sample_hash[i]) >> 1);
  }
#else
  const hn::ScalableTag<std::uint64_t> d;
  const std::size_t lanes = hn::Lanes(d);
  const auto vh = hn::Set(d, h);
  const auto bit = hn::Set(d, kPingSampleKeyBit);
  std::size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto k = splitmix64(d, hn::Xor(vh, hn::LoadU(d, sample_hash + i)));
    hn::StoreU(hn::Or(bit, hn::ShiftRight<1>(k)), d, keys + i);
  }
  for (; i < n; ++i) {
    keys[i] = kPingSampleKeyBit | (sonarsynth::splitmix64(h ^ sample_hash[i]) >> 1);
  }
#endif
}

void ground_cell_keys(const CellFrame& f, const SampleClass* cls, const double* gy,
                      const double* gz, const std::uint64_t* noise_keys, std::size_t n,
                      std::uint64_t* keys) {
#if HWY_TARGET == HWY_SCALAR || HWY_TARGET == HWY_EMU128
  // The portable targets: the scalar loop (runs of samples in one cell share its key).
  Cell last;
  std::uint64_t last_key = 0;
  bool have_last = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (cls[i] != SampleClass::seabed && cls[i] != SampleClass::object) {
      keys[i] = noise_keys[i];
      continue;
    }
    const Cell c = cell_at(f, gy[i], gz[i]);
    if (!have_last || !(c == last)) {
      last_key = ground_cell_key(c.ix, c.iy, c.iz);
      last = c;
      have_last = true;
    }
    keys[i] = last_key;
  }
#else
  const hn::ScalableTag<double> dd;
  const hn::RebindToUnsigned<decltype(dd)> du;
  const hn::Rebind<std::uint32_t, decltype(du)> du32;
  const hn::Rebind<std::uint8_t, decltype(du)> du8;
  const std::size_t lanes = hn::Lanes(dd);
  const auto nx = hn::Set(dd, f.nx), ny = hn::Set(dd, f.ny);
  const auto dx = hn::Set(dd, f.dx), dy = hn::Set(dd, f.dy), inv = hn::Set(dd, f.inv_cell);
  const auto lo_xy = hn::Set(dd, -0x1p22), hi_xy = hn::Set(dd, 0x1p22);
  const auto lo_z = hn::Set(dd, -0x1p15), hi_z = hn::Set(dd, 0x1p15);
  // 2^52 + 2^51 + k for an integer |k| < 2^51 is exact and in [2^52, 2^53), where the mantissa
  // counts units: its low m bits are k mod 2^m (m <= 51).
  const auto two52 = hn::Set(dd, 0x1.8p52);
  const auto mask23 = hn::Set(du, 0x7fffffULL), mask16 = hn::Set(du, 0xffffULL);
  const auto mask62 = hn::Set(du, (std::uint64_t{1} << 62) - 1);
  const auto tag62 = hn::Set(du, std::uint64_t{1} << 62);
  const auto seabed = hn::Set(du, static_cast<std::uint64_t>(SampleClass::seabed));
  const auto object = hn::Set(du, static_cast<std::uint64_t>(SampleClass::object));
  const auto low_bits = [&](hn::Vec<decltype(dd)> v, hn::Vec<decltype(du)> mask) {
    return hn::And(hn::BitCast(du, hn::Add(v, two52)), mask);
  };
  std::size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto c = hn::PromoteTo(
        du, hn::PromoteTo(du32, hn::LoadU(du8, reinterpret_cast<const std::uint8_t*>(cls + i))));
    const auto ground = hn::Or(hn::Eq(c, seabed), hn::Eq(c, object));
    const auto nk = hn::LoadU(du, noise_keys + i);
    if (hn::AllFalse(du, ground)) {
      hn::StoreU(nk, du, keys + i);
      continue;
    }
    const auto y = hn::LoadU(dd, gy + i);
    const auto fx = hn::Floor(hn::Mul(hn::Add(nx, hn::Mul(y, dx)), inv));
    const auto fy = hn::Floor(hn::Mul(hn::Add(ny, hn::Mul(y, dy)), inv));
    const auto fz = hn::Floor(hn::Mul(hn::LoadU(dd, gz + i), inv));
    const auto packed = hn::And(hn::And(hn::And(hn::Ge(fx, lo_xy), hn::Lt(fx, hi_xy)),
                                        hn::And(hn::Ge(fy, lo_xy), hn::Lt(fy, hi_xy))),
                                hn::And(hn::Ge(fz, lo_z), hn::Lt(fz, hi_z)));
    auto x = hn::Or(
        hn::Or(hn::ShiftLeft<39>(low_bits(fx, mask23)), hn::ShiftLeft<16>(low_bits(fy, mask23))),
        low_bits(fz, mask16));
    x = hn::And(mul64(du, x, 0xbf58476d1ce4e5b9ULL), mask62);
    x = hn::Xor(x, hn::ShiftRight<31>(x));
    x = hn::And(mul64(du, x, 0x94d049bb133111ebULL), mask62);
    x = hn::Or(tag62, hn::Xor(x, hn::ShiftRight<29>(x)));
    hn::StoreU(hn::IfThenElse(ground, x, nk), du, keys + i);
    // Lanes of a ground sample beyond the packed range (or not finite): the scalar function.
    const auto rare = hn::AndNot(hn::RebindMask(du, packed), ground);
    if (!hn::AllFalse(du, rare)) {
      for (std::size_t j = i; j < i + lanes; ++j) {
        if (cls[j] == SampleClass::seabed || cls[j] == SampleClass::object) {
          keys[j] = ground_cell_key_at(f, gy[j], gz[j]);
        }
      }
    }
  }
  for (; i < n; ++i) {
    const bool ground_i = cls[i] == SampleClass::seabed || cls[i] == SampleClass::object;
    keys[i] = ground_i ? ground_cell_key_at(f, gy[i], gz[i]) : noise_keys[i];
  }
#endif
}

}  // namespace sonarsynth::sample_keys::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sonarsynth::sample_keys {

HWY_EXPORT(ping_keys);
HWY_EXPORT(ground_cell_keys);

void ping_keys(std::uint64_t h, const std::uint64_t* sample_hash, std::size_t n,
               std::uint64_t* keys) {
  simd::configure_from_environment();
  HWY_DYNAMIC_DISPATCH(ping_keys)(h, sample_hash, n, keys);
}

void ground_cell_keys(const CellFrame& f, const SampleClass* cls, const double* gy,
                      const double* gz, const std::uint64_t* noise_keys, std::size_t n,
                      std::uint64_t* keys) {
  simd::configure_from_environment();
  HWY_DYNAMIC_DISPATCH(ground_cell_keys)(f, cls, gy, gz, noise_keys, n, keys);
}

}  // namespace sonarsynth::sample_keys
#endif  // HWY_ONCE
