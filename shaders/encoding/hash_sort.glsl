// Shared by the sort-and-reduce backward of the hash encoding (HashBackwardMode::SortReduce):
// encode_hash_backward_count.comp, _scatter.comp and _reduce.comp. The table gradient is computed
// without float atomics: contributions are counting-sorted by table entry, then each entry's list
// is summed by one invocation (or, for entries longer than a chunk of slots, by several whose
// partial sums are combined exactly).
#ifndef VKNERF_HASH_SORT_GLSL
#define VKNERF_HASH_SORT_GLSL

#ifdef HASH_SORT_SAMPLES
// Count and scatter: one invocation per sample of rows [rowBase, rowBase + count) of the bound
// chunk, levels [levelBegin, levelEnd) of the pass. Entry e of the pass is
// ((l - levelBegin) << LOG2_TABLE) + index: the table's own level-major order, offset by the pass.
#include "encoding/hash_sort_shared.h"
#include "gpu/row_limit.glsl"

// Whether row rowBase + i of the bound chunk is one of this pass's samples (and below the row limit).
bool sortSampleLive(uint i) { return i < pc.count && pc.rowBase + i < limitedRows(pc.rowBase + pc.count, pc.limitBase); }
#endif

// ---- Exact, order-independent sums in 64-bit fixed point (two uints, two's complement) ----
// The slot order within an entry comes from atomic cursors, so it changes from run to run; a float
// sum in that order would change in its last bits too. Instead every term is rounded once to a
// fixed-point integer on a grid chosen per entry (from the entry's max |term| and term count, so
// no sum can overflow), and integers add exactly in any order: the result is deterministic, and
// more accurate than a float sum: n terms lose at most n^2 2^-60 max|term| to the grid (a float sum
// up to n 2^-24 sum|term|), plus two roundings converting the total back to float.
// uvec2 = (low word, high word). No int64 types: they need shaderInt64, which not every device has.

// 2^k for k in [-126, 127], built from the bits (exact).
float pow2i(int k) { return uintBitsToFloat(uint(k + 127) << 23); }
// v * 2^s for s in [-252, 254] without an overflowing or underflowing intermediate.
float scalePow2(float v, int s) { return v * pow2i(s / 2) * pow2i(s - s / 2); }

// Grid exponent for n terms of magnitude <= maxAbs: each term scaled by 2^s is < 2^(61 - b) with
// n <= 2^b, so the sum stays below 2^61 (rounding included). 0 for maxAbs == 0 (all terms zero).
int fixedShift(float maxAbs, uint n) {
  if (!(maxAbs > 0.0)) return 0;
  int e;
  frexp(maxAbs, e);  // maxAbs < 2^e
  int b = findMSB(max(n, 1u)) + 1;  // n < 2^b
  return 61 - b - e;
}

uvec2 negate64(uvec2 a) {
  uint lo = ~a.x + 1u;
  return uvec2(lo, ~a.y + (lo == 0u ? 1u : 0u));
}

uvec2 add64(uvec2 a, uvec2 b) {
  uint carry;
  uint lo = uaddCarry(a.x, b.x, carry);
  return uvec2(lo, a.y + b.y + carry);
}

// round(v * 2^s) as a 64-bit integer; |v| * 2^s < 2^61 by the choice of s.
uvec2 toFixed(float v, int s) {
  float a = round(scalePow2(abs(v), s));
  float hi = floor(a * (1.0 / 4294967296.0));
  float lo = a - hi * 4294967296.0;  // exact: a has 24 significant bits
  uvec2 r = uvec2(uint(lo), uint(hi));
  return v < 0.0 ? negate64(r) : r;
}

float fromFixed(uvec2 r, int s) {
  bool neg = (r.y & 0x80000000u) != 0u;
  if (neg) r = negate64(r);
  float m = float(r.y) * 4294967296.0 + float(r.x);
  return scalePow2(neg ? -m : m, -s);
}

#endif
