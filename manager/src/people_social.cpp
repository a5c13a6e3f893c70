// The social force between people in cut-off mode: all pairs of the neighbour grid within the
// cut-off, in batches. The loops that compute a batch have no branch and no library call, so the
// compiler vectorises them (AVX-512 or AVX2 where the CPU has it, else SSE2). The two
// approximations are polyAtan2 (error < 1e-10 rad) and polyExp (relative error < 1e-15);
// everything else is the formula of section 1.5 as hunav::socialForceFrom computes it. No FMA
// (-ffp-contract=off), so the AVX-512, AVX2 and SSE2 paths and the scalar unweightedSocialForce
// give bit-identical results on any x86-64 CPU (libm's exp does not: glibc picks an FMA variant at
// run time). Sums are accumulated in forEachPair's order.
#include "people_social.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "poly_math.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace hunav::manager {

namespace {

using detail::polyAtan2;
using detail::polyExp;

struct KernelParams {
  double lambda, gamma, n_angle, n_velocity;
  double inv_gamma;                // 1 / gamma
  double negligible_reach2 = 0.0;  // (gamma ln(1/tolerance))^2; 0: every pair within the cut-off
};

// The social force of the other body on me without omega_s (section 1.5), from d = other - me and
// dv = v_me - v_other, in three stages (the batch runs each stage over all its pairs: short loop
// bodies, so the CPU overlaps the long dependency chains of the polynomials of many pairs).
// Stage 1: distance, interaction vector D = lambda dv + e, t = D/|D|, B = gamma |D|, and the two
// arguments of atan2 (theta = angle from t to e, the same as from D to e).
inline void pairGeometry(double dx, double dy, double dvx, double dvy, const KernelParams& p, double& tx, double& ty,
                         double& d_over_b, double& b, double& sin_theta, double& cos_theta) {
  const double d2 = dx * dx + dy * dy;
  const double d = std::sqrt(d2 > 0.0 ? d2 : 1.0), inv_d = 1.0 / d;
  const double ex = dx * inv_d, ey = dy * inv_d;
  const double Dx = p.lambda * dvx + ex;
  const double Dy = p.lambda * dvy + ey;
  const double len2 = Dx * Dx + Dy * Dy;
  const double len = std::sqrt(len2 > 0.0 ? len2 : 1.0), inv_len = 1.0 / len;
  b = p.gamma * len;
  d_over_b = d * inv_len * p.inv_gamma;
  tx = Dx * inv_len;
  ty = Dy * inv_len;
  // theta from D itself (atan2 does not depend on the length): when dv = 0, D is e bit for bit and
  // the cross product is exactly 0, so theta = 0 and there is no sideways force, as in
  // hunav::socialForceFrom; from t = D/|D| rounding could leave +-1e-17 and a full sideways push.
  sin_theta = Dx * ey - Dy * ex;
  cos_theta = Dx * ex + Dy * ey;
  // Coincident bodies, or D = 0: no direction, no force (the NaN guard); marked by d/B < 0.
  d_over_b = (d2 > 0.0 && len2 > 0.0) ? d_over_b : -1.0;
}

// Stage 3: the force from theta (stage 2 is polyAtan2).
inline void pairForce(double tx, double ty, double d_over_b, double b, double theta, const KernelParams& p, double& ux,
                      double& uy) {
  const double q = p.n_angle * b * theta, qp = p.n_velocity * b * theta;
  const double fv = -polyExp(-d_over_b - qp * qp);
  const double sign = theta > 0.0 ? 1.0 : (theta < 0.0 ? -1.0 : 0.0);
  const double ft = -sign * polyExp(-d_over_b - q * q);
  const double fx = fv * tx - ft * ty, fy = fv * ty + ft * tx;
  const bool force = d_over_b >= 0.0;
  ux = force ? fx : 0.0;
  uy = force ? fy : 0.0;
}

constexpr int kBatch = 128;
constexpr int kBatchSlack = 8;  // appendPairs may store one group of 8 beyond kBatch

// One batch of pairs (i, j): the differences, the intermediate values and the force of j on i.
struct PairBatch {
  static constexpr int kSize = kBatch + kBatchSlack;
  alignas(64) double dx[kSize];  // x_j - x_i
  alignas(64) double dy[kSize];
  alignas(64) double dvx[kSize];  // vx_i - vx_j
  alignas(64) double dvy[kSize];
  alignas(64) double tx[kSize];
  alignas(64) double ty[kSize];
  alignas(64) double d_over_b[kSize];
  alignas(64) double b[kSize];
  alignas(64) double sin_theta[kSize];
  alignas(64) double cos_theta[kSize];
  alignas(64) double theta[kSize];
  alignas(64) double ux[kSize];
  alignas(64) double uy[kSize];
  alignas(64) double keep[kSize];  // with a tolerance: 1 when the pair's force may reach it, else 0
  alignas(64) int i[kSize];
  alignas(64) int j[kSize + 8];
};

__attribute__((always_inline)) inline void batchLoop(PairBatch& s, int n, const KernelParams& p) {
  for (int l = 0; l < n; ++l)
    pairGeometry(s.dx[l], s.dy[l], s.dvx[l], s.dvy[l], p, s.tx[l], s.ty[l], s.d_over_b[l], s.b[l], s.sin_theta[l],
                 s.cos_theta[l]);
  for (int l = 0; l < n; ++l) s.theta[l] = polyAtan2(s.sin_theta[l], s.cos_theta[l]);
  for (int l = 0; l < n; ++l) pairForce(s.tx[l], s.ty[l], s.d_over_b[l], s.b[l], s.theta[l], p, s.ux[l], s.uy[l]);
}

// keep[l] for the pairs [from, n): 0 when the pair's force is certainly below the tolerance
// (dropNegligiblePairs). No branch, no library call but the square root: vectorised as batchLoop.
__attribute__((always_inline)) inline void keepLoop(PairBatch& s, int from, int n, const KernelParams& p) {
  const double lambda2 = p.lambda * p.lambda, two_lambda = 2.0 * p.lambda, reach2 = p.negligible_reach2;
  for (int l = from; l < n; ++l) {
    const double dx = s.dx[l], dy = s.dy[l], dvx = s.dvx[l], dvy = s.dvy[l];
    const double d2 = dx * dx + dy * dy;
    const double d = std::sqrt(d2 > 0.0 ? d2 : 1.0);
    const double len2 = lambda2 * (dvx * dvx + dvy * dvy) + two_lambda * (dvx * dx + dvy * dy) / d + 1.0;
    s.keep[l] = d2 <= reach2 * len2 ? 1.0 : 0.0;
  }
}

// The bodies in the grid's order (structure of arrays).
struct Bodies {
  const double *x, *y, *vx, *vy;
};

// Appends to the batch the pairs (k, m), m = from, from + 1, ..., within sqrt(r2) of body k (the
// test dx*dx + dy*dy <= r2, no branch on it), until m reaches `to` or the batch holds kBatch pairs;
// returns the m it stopped at.
inline int appendPairsScalar(const Bodies& g, int k, int from, int to, double r2, PairBatch& b, int& n) {
  const double *x = g.x, *y = g.y, *vx = g.vx, *vy = g.vy;  // locals: the batch stores cannot alias them
  const double xk = x[k], yk = y[k], vxk = vx[k], vyk = vy[k];
  int count = n;  // a local: the stores into the batch cannot alias it
  int m = from;
  for (; m < to && count < kBatch; ++m) {
    const double dx = x[m] - xk, dy = y[m] - yk;
    b.dx[count] = dx;
    b.dy[count] = dy;
    b.dvx[count] = vxk - vx[m];
    b.dvy[count] = vyk - vy[m];
    b.i[count] = k;
    b.j[count] = m;
    count += dx * dx + dy * dy <= r2 ? 1 : 0;
  }
  n = count;
  return m;
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define HUNAV_X86_SIMD 1
// AVX2 only, never FMA: the same roundings as the baseline code.
__attribute__((target("avx2"))) void batchAvx2(PairBatch& b, int n, const KernelParams& p) { batchLoop(b, n, p); }
// AVX-512 (8 pairs per instruction; again no FMA).
__attribute__((target("avx512f,avx512dq,prefer-vector-width=512"))) void batchAvx512(PairBatch& b, int n,
                                                                                     const KernelParams& p) {
  batchLoop(b, n, p);
}
// The tolerance's test, the same two ways.
__attribute__((target("avx2"))) void keepAvx2(PairBatch& b, int from, int n, const KernelParams& p) {
  keepLoop(b, from, n, p);
}
__attribute__((target("avx512f,avx512dq,prefer-vector-width=512"))) void keepAvx512(PairBatch& b, int from, int n,
                                                                                    const KernelParams& p) {
  keepLoop(b, from, n, p);
}
// What the CPU offers, asked once (after __builtin_cpu_init, whatever the order of static initialisers).
bool haveAvx512() {
  static const bool yes =
      (__builtin_cpu_init(), __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq"));
  return yes;
}
bool haveAvx2() {
  static const bool yes = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
  return yes;
}

// appendPairsScalar eight candidates at a time: the lanes that pass are packed by vcompress.
__attribute__((target("avx512f,avx512dq"))) int appendPairsAvx512(const Bodies& g, int k, int from, int to, double r2,
                                                                  PairBatch& b, int& n) {
  const double *x = g.x, *y = g.y, *vx = g.vx, *vy = g.vy;  // locals: the batch stores cannot alias them
  const __m512d xk = _mm512_set1_pd(x[k]), yk = _mm512_set1_pd(y[k]);
  const __m512d vxk = _mm512_set1_pd(vx[k]), vyk = _mm512_set1_pd(vy[k]), vr2 = _mm512_set1_pd(r2);
  const __m256i vk = _mm256_set1_epi32(k);
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 0, 0, 0, 0, 0, 0, 0, 0);
  int count = n;
  int m = from;
  for (; m + 8 <= to && count < kBatch; m += 8) {
    const __m512d dx = _mm512_sub_pd(_mm512_loadu_pd(x + m), xk);
    const __m512d dy = _mm512_sub_pd(_mm512_loadu_pd(y + m), yk);
    const __m512d d2 = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
    const __mmask8 pass = _mm512_cmp_pd_mask(d2, vr2, _CMP_LE_OQ);
    _mm512_storeu_pd(b.dx + count, _mm512_maskz_compress_pd(pass, dx));
    _mm512_storeu_pd(b.dy + count, _mm512_maskz_compress_pd(pass, dy));
    _mm512_storeu_pd(b.dvx + count, _mm512_maskz_compress_pd(pass, _mm512_sub_pd(vxk, _mm512_loadu_pd(vx + m))));
    _mm512_storeu_pd(b.dvy + count, _mm512_maskz_compress_pd(pass, _mm512_sub_pd(vyk, _mm512_loadu_pd(vy + m))));
    const __m512i j = _mm512_maskz_compress_epi32(pass, _mm512_add_epi32(lane, _mm512_set1_epi32(m)));
    _mm512_storeu_si512(b.j + count, j);  // 16 lanes: j has room for them
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(b.i + count), vk);
    count += __builtin_popcount(static_cast<unsigned>(pass));
  }
  n = count;
  return n < kBatch ? appendPairsScalar(g, k, m, to, r2, b, n) : m;
}

__attribute__((target("avx2"), always_inline)) inline __m256d pack(__m256d v, __m256i order) {
  return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), order));
}

// appendPairsScalar four candidates at a time: the lanes that pass the test are packed to the front
// (a permutation from a table, indexed by the test's bit mask) and stored.
__attribute__((target("avx2"))) int appendPairsAvx2(const Bodies& g, int k, int from, int to, double r2, PairBatch& b,
                                                    int& n) {
  // For each 4-bit mask, the 32-bit lanes of the passing doubles first (the rest: don't care).
  alignas(32) static const int kPack[16][8] = {
      {0, 1, 0, 1, 0, 1, 0, 1}, {0, 1, 0, 1, 0, 1, 0, 1}, {2, 3, 0, 1, 0, 1, 0, 1}, {0, 1, 2, 3, 0, 1, 0, 1},
      {4, 5, 0, 1, 0, 1, 0, 1}, {0, 1, 4, 5, 0, 1, 0, 1}, {2, 3, 4, 5, 0, 1, 0, 1}, {0, 1, 2, 3, 4, 5, 0, 1},
      {6, 7, 0, 1, 0, 1, 0, 1}, {0, 1, 6, 7, 0, 1, 0, 1}, {2, 3, 6, 7, 0, 1, 0, 1}, {0, 1, 2, 3, 6, 7, 0, 1},
      {4, 5, 6, 7, 0, 1, 0, 1}, {0, 1, 4, 5, 6, 7, 0, 1}, {2, 3, 4, 5, 6, 7, 0, 1}, {0, 1, 2, 3, 4, 5, 6, 7}};
  const double *x = g.x, *y = g.y, *vx = g.vx, *vy = g.vy;  // locals: the batch stores cannot alias them
  const __m256d xk = _mm256_set1_pd(x[k]), yk = _mm256_set1_pd(y[k]);
  const __m256d vxk = _mm256_set1_pd(vx[k]), vyk = _mm256_set1_pd(vy[k]), vr2 = _mm256_set1_pd(r2);
  const __m128i vk = _mm_set1_epi32(k);
  int count = n;  // a local: the stores into the batch cannot alias it
  int m = from;
  for (; m + 4 <= to && count < kBatch; m += 4) {
    const __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(x + m), xk);
    const __m256d dy = _mm256_sub_pd(_mm256_loadu_pd(y + m), yk);
    const __m256d d2 = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
    const int mask = _mm256_movemask_pd(_mm256_cmp_pd(d2, vr2, _CMP_LE_OQ));
    const __m256i order = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack[mask]));
    _mm256_storeu_pd(b.dx + count, pack(dx, order));
    _mm256_storeu_pd(b.dy + count, pack(dy, order));
    _mm256_storeu_pd(b.dvx + count, pack(_mm256_sub_pd(vxk, _mm256_loadu_pd(vx + m)), order));
    _mm256_storeu_pd(b.dvy + count, pack(_mm256_sub_pd(vyk, _mm256_loadu_pd(vy + m)), order));
    // j: the lane numbers are the even 32-bit lanes of `order` halved.
    const __m256i lanes = _mm256_srli_epi32(order, 1);
    const __m128i j = _mm_add_epi32(
        _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(lanes, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6))),
        _mm_set1_epi32(m));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(b.j + count), j);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(b.i + count), vk);
    count += __builtin_popcount(static_cast<unsigned>(mask));
  }
  n = count;
  return n < kBatch ? appendPairsScalar(g, k, m, to, r2, b, n) : m;
}
#endif

void computeBatch(PairBatch& b, int n, const KernelParams& p) {
#ifdef HUNAV_X86_SIMD
  if (haveAvx512()) return batchAvx512(b, n, p);
  if (haveAvx2()) return batchAvx2(b, n, p);
#endif
  batchLoop(b, n, p);
}

int appendPairs(const Bodies& g, int k, int from, int to, double r2, PairBatch& b, int& n) {
#ifdef HUNAV_X86_SIMD
  if (haveAvx512()) return appendPairsAvx512(g, k, from, to, r2, b, n);
  if (haveAvx2()) return appendPairsAvx2(g, k, from, to, r2, b, n);
#endif
  return appendPairsScalar(g, k, from, to, r2, b, n);
}

KernelParams kernelParams(const SfmParams& p) { return KernelParams{p.lambda, p.gamma, p.n, p.n_prime, 1.0 / p.gamma}; }

// Removes from the batch (keeping the order) the pairs whose force is certainly below the
// tolerance: |u| <= sqrt(2) exp(-d/B) with B = gamma |D| (both exponentials of pairForce are at
// most exp(-d/B)), so exp(-d/B) < tolerance, that is d > gamma |D| ln(1/tolerance), bounds |u|
// by tolerance times the largest force of one pair (sqrt(2)). reach2 = (gamma ln(1/tolerance))^2,
// the test d^2 > reach2 |D|^2, with |D|^2 = lambda^2 |dv|^2 + 2 lambda dv.e + 1 (keepLoop): a square
// root and a division, no exp or atan2. Coincident bodies are kept (pairForce gives them no force).
// Pairs [0, from) were checked before; returns the pairs left.
int dropNegligiblePairs(PairBatch& b, int from, int n, const KernelParams& p) {
#ifdef HUNAV_X86_SIMD
  if (haveAvx512())
    keepAvx512(b, from, n, p);
  else if (haveAvx2())
    keepAvx2(b, from, n, p);
  else
#endif
    keepLoop(b, from, n, p);
  int out = from;
  for (int l = from; l < n; ++l) {
    b.dx[out] = b.dx[l];
    b.dy[out] = b.dy[l];
    b.dvx[out] = b.dvx[l];
    b.dvy[out] = b.dvy[l];
    b.i[out] = b.i[l];
    b.j[out] = b.j[l];
    out += b.keep[l] != 0.0 ? 1 : 0;
  }
  return out;
}

}  // namespace

Vec2 unweightedSocialForce(const SfmBody& me, const SfmBody& o, const SfmParams& p) {
  const KernelParams kp = kernelParams(p);
  double tx, ty, d_over_b, b, sin_theta, cos_theta;
  pairGeometry(o.position.x() - me.position.x(), o.position.y() - me.position.y(), me.velocity.x() - o.velocity.x(),
               me.velocity.y() - o.velocity.y(), kp, tx, ty, d_over_b, b, sin_theta, cos_theta);
  Vec2 u;
  pairForce(tx, ty, d_over_b, b, polyAtan2(sin_theta, cos_theta), kp, u.x(), u.y());
  return u;
}

namespace {

// What the pair loops read of a NeighborGrid.
struct GridView {
  Bodies bodies;
  const int* start;  // nx*ny+1 offsets of the cells' bodies
  int nx, ny;
};

// The forces of the pairs of a range of cells [cell_from, cell_to), computed batch by batch in
// `*batch`; each computed batch goes to `sink(batch, n)` in forEachPair's order (the sink may point
// `batch` to another batch to fill next).
template <class Sink>
void pairsOfCells(const GridView& g, int cell_from, int cell_to, double r2, const KernelParams& kp, PairBatch*& batch,
                  Sink&& sink) {
  int n = 0;
  int checked = 0;  // with a tolerance: the batch's first pairs, already found not negligible
  const bool tolerance = kp.negligible_reach2 > 0.0;
  auto pairsWith = [&](int k, int from, int to) {
    for (int m = from; m < to;) {
      m = appendPairs(g.bodies, k, m, to, r2, *batch, n);
      if (n < kBatch) continue;
      // With a tolerance a full batch first loses its negligible pairs, and fills up again while
      // less than half of it is left (a nearly empty batch costs as much as a full one).
      if (tolerance) checked = n = dropNegligiblePairs(*batch, checked, n, kp);
      if (n >= kBatch / 2 || !tolerance) {
        computeBatch(*batch, n, kp);
        sink(batch, n);
        n = checked = 0;
      }
    }
  };
  const int nx = g.nx, ny = g.ny;
  const int* start = g.start;
  for (int c = cell_from; c < cell_to; ++c) {
    const int cy = c / nx, cx = c % nx;
    // The rest of this cell and the cell to the right are contiguous in the grid's order, and so
    // are the three cells of the next row: forEachPair's order is kept.
    const int same_to = start[cx + 1 < nx ? c + 2 : c + 1];
    const bool next_row = cy + 1 < ny;
    const int row_from = next_row ? start[(cy + 1) * nx + std::max(cx - 1, 0)] : 0;
    const int row_to = next_row ? start[(cy + 1) * nx + std::min(cx + 1, nx - 1) + 1] : 0;
    for (int k = start[c]; k < start[c + 1]; ++k) {
      pairsWith(k, k + 1, same_to);
      pairsWith(k, row_from, row_to);
    }
  }
  if (tolerance) n = dropNegligiblePairs(*batch, checked, n, kp);
  if (n > 0) {
    computeBatch(*batch, n, kp);
    sink(batch, n);
  }
}

// fx[i] += u, fx[j] -= u in pair order. The pairs of one i are consecutive and their j are later
// bodies, so i's sum stays in a register for the run (the same additions in the same order).
void accumulate(const int* pi, const int* pj, const double* ux, const double* uy, int n, double* fx, double* fy) {
  for (int l = 0; l < n;) {
    const int i = pi[l];
    double sx = fx[i], sy = fy[i];
    for (; l < n && pi[l] == i; ++l) {
      sx += ux[l];
      sy += uy[l];
      fx[pj[l]] -= ux[l];
      fy[pj[l]] -= uy[l];
    }
    fx[i] = sx;
    fy[i] = sy;
  }
}

// The pairs of the later cells, in chunks of cells computed on any slot of the pool. Each chunk
// keeps its forces (i, j, u); they are added after the earlier cells' in chunk order, that is in
// pair order, so the sums are the same bits as on one thread, whatever thread computed which chunk
// and whatever the timing.
struct LaterPairs {
  static constexpr std::size_t kMaxChunks = 20;  // chunks of at least 1/16 of the pairs, +1
  struct Chunk {
    int cell_from = 0, cell_to = 0;
    std::vector<int> i, j;  // the computed pairs and forces, in pair order
    std::vector<double> ux, uy;
  };
  std::vector<Chunk> chunks;
  int count = 0;
  std::size_t largest = 0;  // pairs in the largest chunk seen

  // `chunk_start`: the first cell of each chunk, then the end cell.
  void prepare(const std::vector<int>& chunk_start) {
    count = static_cast<int>(chunk_start.size()) - 1;
    if (chunks.size() < static_cast<std::size_t>(count)) chunks.resize(std::max<std::size_t>(count, kMaxChunks));
    for (int c = 0; c < count; ++c) {
      chunks[static_cast<std::size_t>(c)].cell_from = chunk_start[static_cast<std::size_t>(c)];
      chunks[static_cast<std::size_t>(c)].cell_to = chunk_start[static_cast<std::size_t>(c) + 1];
    }
    // Every chunk gets room for 1.5 times the largest chunk seen (reserved 3 times over): how many
    // chunks there are and which cells they hold change from step to step, and a warm step should
    // not allocate.
    for (Chunk& k : chunks) {
      if (2 * k.i.capacity() < 3 * largest) {
        const std::size_t room = 3 * largest;
        k.i.reserve(room);
        k.j.reserve(room);
        k.ux.reserve(room);
        k.uy.reserve(room);
      }
    }
  }
  // `batch`: the slot's own, hot in the cache, refilled each time; what the sums need of it is
  // copied out (keeping every batch instead: 4 MB of cold stores, measured slower).
  void compute(int c, const GridView& g, double r2, const KernelParams& kp, PairBatch* batch) {
    Chunk& k = chunks[static_cast<std::size_t>(c)];
    k.i.clear();
    k.j.clear();
    k.ux.clear();
    k.uy.clear();
    pairsOfCells(g, k.cell_from, k.cell_to, r2, kp, batch, [&](PairBatch*& full, int n) {
      k.i.insert(k.i.end(), full->i, full->i + n);
      k.j.insert(k.j.end(), full->j, full->j + n);
      k.ux.insert(k.ux.end(), full->ux, full->ux + n);
      k.uy.insert(k.uy.end(), full->uy, full->uy + n);
    });
  }
  void addTo(double* fx, double* fy) {
    for (int c = 0; c < count; ++c) {
      const Chunk& k = chunks[static_cast<std::size_t>(c)];
      largest = std::max(largest, k.i.size());
      accumulate(k.i.data(), k.j.data(), k.ux.data(), k.uy.data(), static_cast<int>(k.i.size()), fx, fy);
    }
  }
};

// Below this many people one thread is faster than handing work over (a hand-over's cost against the
// pair forces' per person: docs/performance.md, "Crowds").
constexpr std::size_t kMinBodiesForHelpers = 256;

// The caller's share of the cells: up to the first cell past `own_share` of the candidate pairs the
// loops test (each body of a cell against the rest of its cell, the cell to the right and three
// cells of the next row). Returns that cell; chunk_start gets the later cells in chunks of about
// 1/kChunks.
int splitCells(const GridView& g, double own_share, std::vector<double>& cost, std::vector<int>& chunk_start) {
  const int cells = g.nx * g.ny;
  constexpr double kChunks = 16.0;  // see LaterPairs::kMaxChunks
  auto bodiesIn = [&](int cx, int cy) {
    return cx < 0 || cx >= g.nx || cy >= g.ny
               ? 0.0
               : static_cast<double>(g.start[cy * g.nx + cx + 1] - g.start[cy * g.nx + cx]);
  };
  cost.resize(static_cast<std::size_t>(cells));
  double total = 0.0;
  for (int c = 0; c < cells; ++c) {
    const int cx = c % g.nx, cy = c / g.nx;
    const double n = bodiesIn(cx, cy);
    cost[static_cast<std::size_t>(c)] = n * (0.5 * n + bodiesIn(cx + 1, cy) + bodiesIn(cx - 1, cy + 1) +
                                             bodiesIn(cx, cy + 1) + bodiesIn(cx + 1, cy + 1));
    total += cost[static_cast<std::size_t>(c)];
  }
  int split = 0;
  for (double sum = 0.0; split < cells && sum < own_share * total; ++split)
    sum += cost[static_cast<std::size_t>(split)];
  // The later cells in chunks of about 1/kChunks of the total.
  chunk_start.assign(1, split);
  double chunk_sum = 0.0;
  for (int c = split; c < cells; ++c) {
    chunk_sum += cost[static_cast<std::size_t>(c)];
    if (chunk_sum >= total / kChunks && c + 1 < cells) {
      chunk_start.push_back(c + 1);
      chunk_sum = 0.0;
    }
  }
  chunk_start.push_back(cells);
  return split;
}

}  // namespace

// Scratch of the kernel, reused from step to step.
struct PeopleSocialForces::Workspace {
  std::vector<PairBatch> batches;  // one per slot of the pool (the caller's first)
  std::vector<double> fx, fy;      // sums, in the grid's order
  std::vector<double> cell_cost;   // pairs tested per cell (to split the work between threads)
  std::vector<int> chunk_start;    // the later cells' chunks
  LaterPairs later;
};

bool crowdWorthSharing(const ThreadPool* threads, std::size_t people) {
  return threads != nullptr && threads->slots() > 1 && people >= kMinBodiesForHelpers;
}

PeopleSocialForces::PeopleSocialForces() : ws_(std::make_unique<Workspace>()) {}
PeopleSocialForces::~PeopleSocialForces() = default;

void PeopleSocialForces::compute(StepSnapshot& snap, const NeighborGrid& grid, double cutoff, ThreadPool* threads,
                                 double tolerance) {
  Workspace& ws = *ws_;
  const std::size_t count = grid.items_.size();
  snap.people_social.assign(snap.agents.size(), Vec2::Zero());
  if (count == 0) return;
  const SfmParams p;  // lambda, gamma, n, n' are the same for everybody; omega_s is applied per agent
  KernelParams kp = kernelParams(p);
  if (tolerance > 0.0) kp.negligible_reach2 = std::pow(p.gamma * std::log(1.0 / tolerance), 2);
  const double r2 = cutoff * cutoff;
  const GridView g{Bodies{grid.x_.data(), grid.y_.data(), grid.vx_.data(), grid.vy_.data()}, grid.start_.data(),
                   grid.nx_, grid.ny_};
  const bool share = crowdWorthSharing(threads, count);
  const std::size_t slots = share ? static_cast<std::size_t>(threads->slots()) : 1;
  if (ws.batches.size() < slots) ws.batches.resize(slots);
  ws.fx.assign(count, 0.0);
  ws.fy.assign(count, 0.0);
  double* fx = ws.fx.data();
  double* fy = ws.fy.data();
  const int cells = g.nx * g.ny;
  auto sink = [fx, fy](PairBatch*& b, int n) { accumulate(b->i, b->j, b->ux, b->uy, n, fx, fy); };

  if (!share) {
    PairBatch* batch = ws.batches.data();
    pairsOfCells(g, 0, cells, r2, kp, batch, sink);
  } else {
    // Item 0 (the caller's, run first): the first cells, summed at once; the caller also adds the
    // chunks afterwards, so it is a little less than a thread's part (0.42 with two).
    // Items 1..: the later cells' chunks, added after it in chunk order.
    const double own_share = 0.84 / static_cast<double>(slots);
    const int split = splitCells(g, own_share, ws.cell_cost, ws.chunk_start);
    ws.later.prepare(ws.chunk_start);
    struct Job {
      Workspace& ws;
      const GridView& g;
      double r2;
      const KernelParams& kp;
      int split;
      const decltype(sink)& first_cells_sink;
      void operator()(int item, int slot) const {
        PairBatch* batch = &ws.batches[static_cast<std::size_t>(slot)];
        if (item == 0)
          pairsOfCells(g, 0, split, r2, kp, batch, first_cells_sink);
        else
          ws.later.compute(item - 1, g, r2, kp, batch);
      }
    } const job{ws, g, r2, kp, split, sink};
    // A closure of one reference: it fits in std::function's own storage (no allocation).
    threads->run(ws.later.count + 1, [&job](int item, int slot) { job(item, slot); });
    ws.later.addTo(fx, fy);
  }
  for (std::size_t k = 0; k < count; ++k) snap.people_social[grid.items_[k]] = Vec2(fx[k], fy[k]);
}

void computePeopleSocial(StepSnapshot& snap, const NeighborGrid& grid, double cutoff, ThreadPool* threads,
                         double tolerance) {
  PeopleSocialForces forces;
  forces.compute(snap, grid, cutoff, threads, tolerance);
}

}  // namespace hunav::manager
