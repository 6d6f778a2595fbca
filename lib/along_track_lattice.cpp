// SPDX-License-Identifier: MIT
#include "sonarsynth/along_track_lattice.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "sonarsynth/keyed_random.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SONARSYNTH_LATTICE_AVX2 1
#endif

namespace sonarsynth {

void lattice_look_scalar(const LatticeSamples& s, std::uint64_t look_offset, double* out) {
  const NormalTable& normal = NormalTable::get();
  for (std::size_t i = 0; i < s.samples; ++i) {
    const double inv_2w2 = s.inv_2w2[i];
    if (std::isnan(inv_2w2)) {
      out[i] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    const std::uint64_t cell = s.cell[i];
    const std::uint64_t p0 = s.pair0[i] + look_offset;
    const std::uint32_t odd = s.odd[i];
    // Scatterer k: g1 from the low 16 bits of one half of the word of its pair, g2 from its
    // high 16 bits: two words per sample, three when the first scatterer is odd.
    std::uint64_t h[3];
    h[0] = splitmix_stream(cell, p0);
    h[1] = splitmix_stream(cell, p0 + 1);
    h[2] = odd != 0 ? splitmix_stream(cell, p0 + 2) : 0;
    float re = 0.0f, im = 0.0f;
    for (std::uint32_t k = 0; k < 4; ++k) {
      const std::uint32_t q = k + odd;  // word q / 2, half q % 2
      const auto half = static_cast<std::uint32_t>(h[q >> 1] >> (32 * (q & 1)));
      re += s.w[k][i] * normal(half);
      im += s.w[k][i] * normal(half >> 16);
    }
    const auto dre = static_cast<double>(re), dim = static_cast<double>(im);
    out[i] = (dre * dre + dim * dim) * inv_2w2;
  }
}

#ifdef SONARSYNTH_LATTICE_AVX2
namespace {

// AVX2 only (no FMA): every product and sum is rounded as in the scalar loop.
#define SONARSYNTH_AVX2 __attribute__((target("avx2")))

// a * c mod 2^64 per 64-bit lane from 32 x 32 -> 64-bit products (c = c_hi 2^32 + c_lo):
// lo(a) c_lo + ((hi(a) c_lo + lo(a) c_hi) mod 2^32) 2^32.
SONARSYNTH_AVX2 inline __m256i mul64(__m256i a, __m256i c_lo, __m256i c_hi) {
  const __m256i lo = _mm256_mul_epu32(a, c_lo);
  const __m256i cross =
      _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), c_lo), _mm256_mul_epu32(a, c_hi));
  return _mm256_add_epi64(lo, _mm256_slli_epi64(cross, 32));
}

struct Mix {
  __m256i gamma, c1_lo, c1_hi, c2_lo, c2_hi;
};

// splitmix64 (keyed_random.hpp) of four 64-bit lanes.
SONARSYNTH_AVX2 inline __m256i splitmix64_x4(__m256i x, const Mix& m) {
  x = _mm256_add_epi64(x, m.gamma);
  x = mul64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 30)), m.c1_lo, m.c1_hi);
  x = mul64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 27)), m.c2_lo, m.c2_hi);
  return _mm256_xor_si256(x, _mm256_srli_epi64(x, 31));
}

// The low (high = false) or high 32-bit halves of the 64-bit lanes of a (samples 0-3) and b
// (samples 4-7), as eight 32-bit lanes in sample order.
SONARSYNTH_AVX2 inline __m256i halves(__m256i a, __m256i b, bool high) {
  const __m256 pa = _mm256_castsi256_ps(a), pb = _mm256_castsi256_ps(b);
  const __m256 t = high ? _mm256_shuffle_ps(pa, pb, _MM_SHUFFLE(3, 1, 3, 1))
                        : _mm256_shuffle_ps(pa, pb, _MM_SHUFFLE(2, 0, 2, 0));
  return _mm256_permute4x64_epi64(_mm256_castps_si256(t), _MM_SHUFFLE(3, 1, 2, 0));
}

SONARSYNTH_AVX2 inline __m256i set64(std::uint64_t v) {
  return _mm256_set1_epi64x(static_cast<long long>(v));
}

SONARSYNTH_AVX2 void lattice_look_avx2(const LatticeSamples& s, std::uint64_t look_offset,
                                       double* out) {
  const float* table = NormalTable::get().data();
  constexpr std::uint64_t kGamma = 0x9e3779b97f4a7c15ULL;
  constexpr std::uint64_t kC1 = 0xbf58476d1ce4e5b9ULL, kC2 = 0x94d049bb133111ebULL;
  const Mix mix{set64(kGamma), set64(kC1 & 0xffffffffULL), set64(kC1 >> 32),
                set64(kC2 & 0xffffffffULL), set64(kC2 >> 32)};
  const __m256i gamma_lo = set64(kGamma & 0xffffffffULL), gamma_hi = set64(kGamma >> 32);
  const __m256i offset = set64(look_offset);
  const __m256i two_gamma = set64(2 * kGamma);
  const __m256i low16 = _mm256_set1_epi32(0xffff);
  const std::size_t blocks = s.samples / 8 * 8;
  for (std::size_t i = 0; i < blocks; i += 8) {
    // The words splitmix_stream(cell, p0 + t) = splitmix64(cell + p0 gamma + t gamma), t = 0..2,
    // of samples i .. i + 3 (a) and i + 4 .. i + 7 (b).
    __m256i w[3][2];
    for (int g = 0; g < 2; ++g) {
      const auto at = static_cast<std::size_t>(4 * g);
      const __m256i cell = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.cell + i + at));
      const __m256i p0 = _mm256_add_epi64(
          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.pair0 + i + at)), offset);
      const __m256i x0 = _mm256_add_epi64(cell, mul64(p0, gamma_lo, gamma_hi));
      w[0][g] = splitmix64_x4(x0, mix);
      w[1][g] = splitmix64_x4(_mm256_add_epi64(x0, mix.gamma), mix);
      w[2][g] = splitmix64_x4(_mm256_add_epi64(x0, two_gamma), mix);
    }
    // The halves in scatterer order: scatterer k of a sample uses half k + odd.
    const __m256i half[5] = {halves(w[0][0], w[0][1], false), halves(w[0][0], w[0][1], true),
                             halves(w[1][0], w[1][1], false), halves(w[1][0], w[1][1], true),
                             halves(w[2][0], w[2][1], false)};
    const __m256i odd = _mm256_sub_epi32(
        _mm256_setzero_si256(), _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.odd + i)));
    __m256 re = _mm256_setzero_ps(), im = _mm256_setzero_ps();
    for (int k = 0; k < 4; ++k) {
      const __m256i h = _mm256_blendv_epi8(half[k], half[k + 1], odd);
      const __m256 g1 = _mm256_i32gather_ps(table, _mm256_and_si256(h, low16), 4);
      const __m256 g2 = _mm256_i32gather_ps(table, _mm256_srli_epi32(h, 16), 4);
      const __m256 wk = _mm256_loadu_ps(s.w[k] + i);
      re = _mm256_add_ps(re, _mm256_mul_ps(wk, g1));
      im = _mm256_add_ps(im, _mm256_mul_ps(wk, g2));
    }
    // NaN normalisation (samples drawn independently) gives the NaN of the scalar loop.
    for (int g = 0; g < 2; ++g) {
      const auto at = static_cast<std::size_t>(4 * g);
      const __m256d dre =
          _mm256_cvtps_pd(g == 0 ? _mm256_castps256_ps128(re) : _mm256_extractf128_ps(re, 1));
      const __m256d dim =
          _mm256_cvtps_pd(g == 0 ? _mm256_castps256_ps128(im) : _mm256_extractf128_ps(im, 1));
      const __m256d sum = _mm256_add_pd(_mm256_mul_pd(dre, dre), _mm256_mul_pd(dim, dim));
      _mm256_storeu_pd(out + i + at, _mm256_mul_pd(sum, _mm256_loadu_pd(s.inv_2w2 + i + at)));
    }
  }
  if (blocks < s.samples) {
    LatticeSamples rest = s;
    for (int k = 0; k < 4; ++k) rest.w[k] += blocks;
    rest.inv_2w2 += blocks;
    rest.cell += blocks;
    rest.pair0 += blocks;
    rest.odd += blocks;
    rest.samples -= blocks;
    lattice_look_scalar(rest, look_offset, out + blocks);
  }
}

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2") != 0;
  return has;
}

}  // namespace
#endif

namespace {

bool simd_allowed_at_start() {
  const char* v = std::getenv("SONARSYNTH_SCALAR");
  return v == nullptr || std::strcmp(v, "1") != 0;
}

std::atomic<bool>& simd_allowed() {
  static std::atomic<bool> allowed{simd_allowed_at_start()};
  return allowed;
}

}  // namespace

bool lattice_simd_active() {
#ifdef SONARSYNTH_LATTICE_AVX2
  return cpu_has_avx2() && simd_allowed().load(std::memory_order_relaxed);
#else
  return false;
#endif
}

void set_lattice_simd(bool allowed) {
  simd_allowed().store(allowed, std::memory_order_relaxed);
}

void lattice_look(const LatticeSamples& s, std::uint64_t look_offset, double* out) {
#ifdef SONARSYNTH_LATTICE_AVX2
  if (lattice_simd_active()) {
    lattice_look_avx2(s, look_offset, out);
    return;
  }
#endif
  lattice_look_scalar(s, look_offset, out);
}

}  // namespace sonarsynth
