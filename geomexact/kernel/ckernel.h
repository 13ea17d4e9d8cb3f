/* C pieces shared by the compiled kernels (geomexact/mesh2d/refinement/engines/lepp_kernel.pyx and
   geomexact/mesh2d/delaunay/delaunay_kernel.pyx), declared for Cython in geomexact/kernel/ckernel.pxd.

   - an open-addressing hash table uint64 -> int64 (keys u << 32 | v);
   - 128-bit helpers and the triangle cell hash of geomexact.kernel.digest;
   - exact predicates on dyadic-grid int64 coordinates (__int128 arithmetic);
   - the certified float filters of geomexact.kernel.predicates2d and .comparisons (same
     formulas, same evaluation order; the including module must be compiled with
     -ffp-contract=off), tested against the exact predicates through
     geomexact/kernel/cfilters.pyx.

   Every function is static: each extension module gets its own copy, and its own copy of
   the constants, which gx_set_constants fills from the Python modules at import. */
#ifndef GEOMEXACT_KERNEL_SUPPORT_H
#define GEOMEXACT_KERNEL_SUPPORT_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>

#if defined(__GNUC__)
#define GX_UNUSED __attribute__((unused))
#else
#define GX_UNUSED
#endif

typedef __int128 gx_i128;
typedef unsigned __int128 gx_u128;

/* ---- open-addressing hash table: uint64 key -> int64 value, linear probing,
   backward-shift deletion (no tombstones), load <= 1/2 ---- */
#define GX_EMPTY UINT64_MAX
/* the key of the half-edge (u, v), ids below 2^32 */
static inline uint64_t gx_edge(int64_t u, int64_t v) { return ((uint64_t)u << 32) | (uint64_t)v; }
typedef struct { uint64_t *keys; int64_t *values; uint64_t mask; uint64_t count; } gx_map;

static inline uint64_t gx_mix(uint64_t x) {
    x ^= x >> 30; x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27; x *= 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}
GX_UNUSED static int gx_map_alloc(gx_map *m, uint64_t slots) {
    m->keys = (uint64_t *)malloc(slots * sizeof(uint64_t));
    m->values = (int64_t *)malloc(slots * sizeof(int64_t));
    if (!m->keys || !m->values) {
        free(m->keys); free(m->values); m->keys = NULL; m->values = NULL; return -1;
    }
    memset(m->keys, 0xff, slots * sizeof(uint64_t));
    m->mask = slots - 1;
    m->count = 0;
    return 0;
}
GX_UNUSED static void gx_map_free(gx_map *m) {
    free(m->keys); free(m->values); m->keys = NULL; m->values = NULL;
}
static inline uint64_t gx_map_slot(const gx_map *m, uint64_t key) {
    uint64_t i = gx_mix(key) & m->mask;
    while (m->keys[i] != GX_EMPTY && m->keys[i] != key) i = (i + 1) & m->mask;
    return i;
}
static inline int64_t gx_map_get(const gx_map *m, uint64_t key, int64_t missing) {
    uint64_t i = gx_map_slot(m, key);
    return m->keys[i] == key ? m->values[i] : missing;
}
/* every entry of ``from`` into ``to`` (allocated, empty, large enough) */
static inline void gx_map_rehash(gx_map *to, const gx_map *from) {
    for (uint64_t i = 0; i <= from->mask; i++) {
        if (from->keys[i] != GX_EMPTY) {
            uint64_t j = gx_map_slot(to, from->keys[i]);
            to->keys[j] = from->keys[i]; to->values[j] = from->values[i]; to->count++;
        }
    }
}
GX_UNUSED static int gx_map_grow(gx_map *m) {
    gx_map old = *m;
    if (gx_map_alloc(m, 2 * (old.mask + 1)) < 0) { *m = old; return -1; }
    gx_map_rehash(m, &old);
    gx_map_free(&old);
    return 0;
}
static inline int gx_map_set(gx_map *m, uint64_t key, int64_t value) {
    uint64_t i = gx_map_slot(m, key);
    if (m->keys[i] == key) { m->values[i] = value; return 0; }
    if (2 * (m->count + 1) > m->mask + 1) {
        if (gx_map_grow(m) < 0) return -1;
        i = gx_map_slot(m, key);
    }
    m->keys[i] = key; m->values[i] = value; m->count++;
    return 0;
}
static inline int gx_map_del(gx_map *m, uint64_t key) {
    uint64_t i = gx_map_slot(m, key), j = i, home;
    if (m->keys[i] != key) return 0;
    for (;;) {
        j = (j + 1) & m->mask;
        if (m->keys[j] == GX_EMPTY) break;
        home = gx_mix(m->keys[j]) & m->mask;
        /* the entry at j may fill the hole at i unless its home lies in (i, j] */
        if (((j - home) & m->mask) >= ((j - i) & m->mask)) {
            m->keys[i] = m->keys[j]; m->values[i] = m->values[j]; i = j;
        }
    }
    m->keys[i] = GX_EMPTY; m->count--;
    return 1;
}

/* ---- 128-bit helpers ---- */
static inline gx_u128 gx_u128_make(uint64_t hi, uint64_t lo) {
    return ((gx_u128)hi << 64) | lo;
}
static inline uint64_t gx_u128_hi(gx_u128 x) { return (uint64_t)(x >> 64); }
static inline uint64_t gx_u128_lo(gx_u128 x) { return (uint64_t)x; }

/* the cell hash of geomexact.kernel.digest: multipliers set once from the Python module */
static gx_u128 gx_m0, gx_m1, gx_m2, gx_mf;
static inline gx_u128 gx_cell_hash(uint64_t ka, uint64_t kb, uint64_t kc) {
    gx_u128 x = (gx_u128)ka * gx_m0 + (gx_u128)kb * gx_m1 + (gx_u128)kc * gx_m2;
    x ^= x >> 61;
    return x * gx_mf;
}

/* ---- exact predicates on grid coordinates (|coordinate| <= 2^60, so every degree-2
   expression below stays under 2^125) ---- */
static inline int gx_sign(gx_i128 v) { return (v > 0) - (v < 0); }
static inline int gx_grid_lengths(int64_t ax, int64_t ay, int64_t bx, int64_t by,
                                  int64_t cx, int64_t cy, int64_t dx, int64_t dy) {
    gx_i128 ux = bx - ax, uy = by - ay, vx = dx - cx, vy = dy - cy;
    return gx_sign((ux * ux + uy * uy) - (vx * vx + vy * vy));
}
static inline int gx_grid_orient(int64_t ax, int64_t ay, int64_t bx, int64_t by,
                                 int64_t cx, int64_t cy) {
    gx_i128 acx = ax - cx, acy = ay - cy, bcx = bx - cx, bcy = by - cy;
    return gx_sign(acx * bcy - acy * bcx);
}
static inline int gx_grid_dot(int64_t px, int64_t py, int64_t ax, int64_t ay,
                              int64_t bx, int64_t by) {
    gx_i128 ux = ax - px, uy = ay - py, vx = bx - px, vy = by - py;
    return gx_sign(ux * vx + uy * vy);
}
static inline gx_i128 gx_grid_area2(int64_t ax, int64_t ay, int64_t bx, int64_t by,
                                    int64_t cx, int64_t cy) {
    gx_i128 ux = bx - ax, uy = by - ay, vx = cx - ax, vy = cy - ay;
    return ux * vy - uy * vx;
}
/* incircle is of degree 4: exact in __int128 once the differences, divided by their
   common power of two, are below 2^30 in magnitude; else 2 (undecided) */
static inline int64_t gx_abs64(int64_t v) { return v < 0 ? -v : v; }
static inline int gx_grid_incircle(int64_t ax, int64_t ay, int64_t bx, int64_t by,
                                   int64_t cx, int64_t cy, int64_t dx, int64_t dy) {
    int64_t d[6] = {ax - dx, ay - dy, bx - dx, by - dy, cx - dx, cy - dy};
    uint64_t bits = 0;
    int k, shift;
    for (k = 0; k < 6; k++) bits |= (uint64_t)d[k];
    if (bits == 0) return 0;
    shift = __builtin_ctzll(bits);
    for (k = 0; k < 6; k++) {
        d[k] >>= shift;  /* exact: every d[k] is a multiple of 2^shift */
        if (gx_abs64(d[k]) > ((int64_t)1 << 30)) return 2;
    }
    {
        gx_i128 adx = d[0], ady = d[1], bdx = d[2], bdy = d[3], cdx = d[4], cdy = d[5];
        gx_i128 det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
                    + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
                    + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
        return gx_sign(det);
    }
}

/* ---- float filters: the formulas of geomexact.kernel.predicates2d (orient2d, incircle),
   .comparisons (squared lengths) and .angles (the dot product), evaluated in the same order (compiled with -ffp-contract=off); 2 means undecided ---- */
static double gx_orient_c, gx_orient_k, gx_incircle_c, gx_incircle_k;
static double gx_lengths_c, gx_lengths_k, gx_dot_c, gx_dot_k;
static inline int gx_float_orient(double ax, double ay, double bx, double by,
                                  double cx, double cy) {
    double acx = ax - cx, acy = ay - cy, bcx = bx - cx, bcy = by - cy;
    double left = acx * bcy, right = acy * bcx, det, t, bound;
    if (left > 0.0) { if (right < 0.0) return 1; }
    else if (left < 0.0 && right > 0.0) return -1;
    det = left - right;
    t = fabs(acx) + fabs(acy) + fabs(bcx) + fabs(bcy) + gx_orient_k;
    bound = t * (fabs(cx) + fabs(cy) + t) * gx_orient_c;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return 2;
}
static inline int gx_float_incircle(double ax, double ay, double bx, double by,
                                    double cx, double cy, double dx, double dy) {
    double adx = ax - dx, ady = ay - dy, bdx = bx - dx, bdy = by - dy;
    double cdx = cx - dx, cdy = cy - dy, det, t, bound;
    det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
        + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
        + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
    t = fabs(adx) + fabs(ady) + fabs(bdx) + fabs(bdy) + fabs(cdx) + fabs(cdy)
        + gx_incircle_k;
    bound = t * t * t * (fabs(dx) + fabs(dy) + t) * gx_incircle_c;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return 2;
}
static inline int gx_float_lengths(double ax, double ay, double bx, double by,
                                   double cx, double cy, double dx, double dy) {
    double ux = bx - ax, uy = by - ay, vx = dx - cx, vy = dy - cy, diff, t, m, bound;
    diff = (ux * ux + uy * uy) - (vx * vx + vy * vy);
    t = fabs(ux) + fabs(uy) + fabs(vx) + fabs(vy) + gx_lengths_k;
    m = fabs(ax) + fabs(ay) + fabs(cx) + fabs(cy);
    bound = t * (m + (t + t)) * gx_lengths_c;
    if (diff > bound) return 1;
    if (-diff > bound) return -1;
    return 2;
}
/* stage 1 of compare_angle: the sign of (a - p).(b - p) */
static inline int gx_float_dot(double px, double py, double ax, double ay,
                               double bx, double by) {
    double ux = ax - px, uy = ay - py, vx = bx - px, vy = by - py, dot, t, mt, bound;
    dot = ux * vx + uy * vy;
    t = fabs(ux) + fabs(uy) + fabs(vx) + fabs(vy) + gx_dot_k;
    mt = fabs(px) + fabs(py) + t;
    bound = t * mt * gx_dot_c;
    if (dot > bound) return 1;
    if (-dot > bound) return -1;
    return 2;
}

/* the constants above, from geomexact.kernel.digest and geomexact.kernel.filter_bounds */
GX_UNUSED static void gx_set_constants(gx_u128 m0, gx_u128 m1, gx_u128 m2, gx_u128 mf,
                                       double orient_c, double orient_k,
                                       double incircle_c, double incircle_k,
                                       double lengths_c, double lengths_k,
                                       double dot_c, double dot_k) {
    gx_m0 = m0; gx_m1 = m1; gx_m2 = m2; gx_mf = mf;
    gx_orient_c = orient_c; gx_orient_k = orient_k;
    gx_incircle_c = incircle_c; gx_incircle_k = incircle_k;
    gx_lengths_c = lengths_c; gx_lengths_k = lengths_k;
    gx_dot_c = dot_c; gx_dot_k = dot_k;
}

/* ---- the vertex hash of geomexact.kernel.digest.vertex_hash for a point on the dyadic
   grid: BLAKE2b-128 (RFC 7693) with personalisation "vertex" of the id (u64, little
   endian) then each coordinate g / 2^F in gmpy2's to_binary encoding of an mpq: 0x03, a
   sign byte (0 zero, 1 positive, 2 negative), then for a non-zero value the numerator's
   byte length (u32, little endian), the numerator's and the denominator's magnitudes in
   their fewest little-endian bytes.  The message (at most 8 + 2 × 22 bytes) is one
   block. ---- */
static const uint64_t gx_blake2b_iv[8] = {
    0x6a09e667f3bcc908ULL, 0xbb67ae8584caa73bULL, 0x3c6ef372fe94f82bULL,
    0xa54ff53a5f1d36f1ULL, 0x510e527fade682d1ULL, 0x9b05688c2b3e6c1fULL,
    0x1f83d9abfb41bd6bULL, 0x5be0cd19137e2179ULL};
static const uint8_t gx_blake2b_sigma[12][16] = {
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
    {14, 10, 4, 8, 9, 15, 13, 6, 1, 12, 0, 2, 11, 7, 5, 3},
    {11, 8, 12, 0, 5, 2, 15, 13, 10, 14, 3, 6, 7, 1, 9, 4},
    {7, 9, 3, 1, 13, 12, 11, 14, 2, 6, 5, 10, 4, 0, 15, 8},
    {9, 0, 5, 7, 2, 4, 10, 15, 14, 1, 11, 12, 6, 8, 3, 13},
    {2, 12, 6, 10, 0, 11, 8, 3, 4, 13, 7, 5, 15, 14, 1, 9},
    {12, 5, 1, 15, 14, 13, 4, 10, 0, 7, 6, 3, 9, 2, 8, 11},
    {13, 11, 7, 14, 12, 1, 3, 9, 5, 0, 15, 4, 8, 6, 2, 10},
    {6, 15, 14, 9, 11, 3, 0, 8, 12, 2, 13, 7, 1, 4, 10, 5},
    {10, 2, 8, 4, 7, 6, 1, 5, 15, 11, 9, 14, 3, 12, 13, 0},
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
    {14, 10, 4, 8, 9, 15, 13, 6, 1, 12, 0, 2, 11, 7, 5, 3}};
static inline uint64_t gx_rotr64(uint64_t x, int n) { return (x >> n) | (x << (64 - n)); }
#define GX_B2B_G(a, b, c, d, x, y) do { \
    v[a] = v[a] + v[b] + (x); v[d] = gx_rotr64(v[d] ^ v[a], 32); \
    v[c] = v[c] + v[d];       v[b] = gx_rotr64(v[b] ^ v[c], 24); \
    v[a] = v[a] + v[b] + (y); v[d] = gx_rotr64(v[d] ^ v[a], 16); \
    v[c] = v[c] + v[d];       v[b] = gx_rotr64(v[b] ^ v[c], 63); } while (0)

/* BLAKE2b (no key) with a digest of `digest_bytes` (8 or 16) of len <= 128 bytes with the
   personalisation whose first 8 bytes are `personal` read little-endian (0: none): the
   digest read as a little-endian integer */
static inline gx_u128 gx_blake2b(const uint8_t *message, unsigned len, uint64_t personal,
                                 unsigned digest_bytes) {
    uint64_t h[8], v[16], m[16];
    uint8_t block[128];
    int i, r;
    const uint8_t *s;
    for (i = 0; i < 8; i++) h[i] = gx_blake2b_iv[i];
    h[0] ^= 0x01010000ULL | digest_bytes;          /* depth 1, fanout 1, no key */
    h[6] ^= personal;
    memset(block, 0, sizeof block);
    memcpy(block, message, len);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy(m, block, sizeof m);
#else
    for (i = 0; i < 16; i++) {
        uint64_t w = 0;
        int k;
        for (k = 7; k >= 0; k--) w = (w << 8) | block[8 * i + k];
        m[i] = w;
    }
#endif
    for (i = 0; i < 8; i++) { v[i] = h[i]; v[i + 8] = gx_blake2b_iv[i]; }
    v[12] ^= (uint64_t)len;  /* the byte counter; its high word stays 0 */
    v[14] = ~v[14];          /* the last block */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 12
#endif
    for (r = 0; r < 12; r++) {
        s = gx_blake2b_sigma[r];
        GX_B2B_G(0, 4, 8, 12, m[s[0]], m[s[1]]);
        GX_B2B_G(1, 5, 9, 13, m[s[2]], m[s[3]]);
        GX_B2B_G(2, 6, 10, 14, m[s[4]], m[s[5]]);
        GX_B2B_G(3, 7, 11, 15, m[s[6]], m[s[7]]);
        GX_B2B_G(0, 5, 10, 15, m[s[8]], m[s[9]]);
        GX_B2B_G(1, 6, 11, 12, m[s[10]], m[s[11]]);
        GX_B2B_G(2, 7, 8, 13, m[s[12]], m[s[13]]);
        GX_B2B_G(3, 4, 9, 14, m[s[14]], m[s[15]]);
    }
    h[0] ^= v[0] ^ v[8];
    if (digest_bytes == 8) return h[0];
    h[1] ^= v[1] ^ v[9];
    return ((gx_u128)h[1] << 64) | h[0];
}
#undef GX_B2B_G

/* BLAKE2b-128 of len <= 128 bytes with the personalisation `personal` (as gx_blake2b) */
static inline gx_u128 gx_blake2b_128(const uint8_t *message, unsigned len,
                                     uint64_t personal) {
    return gx_blake2b(message, len, personal, 16);
}

/* geomexact.kernel.digest.vertex_key: the first 8 bytes (little-endian) of BLAKE2b-64,
   personalisation "vkey", of the id as a little-endian u64 */
static inline uint64_t gx_vertex_key(uint64_t vertex) {
    uint8_t message[8];
    int k;
    for (k = 0; k < 8; k++) message[k] = (uint8_t)(vertex >> (8 * k));
    return (uint64_t)gx_blake2b(message, 8, 0x0000000079656b76ULL, 8);  /* "vkey" */
}

/* gx_vertex_key(vertex), from this module's cache of the keys of 0, 1, ... (grown to
   twice its size or to `vertex`, whichever is more; as digest.vertex_key caches them);
   computed without the cache when it cannot grow (out of memory) */
GX_UNUSED static uint64_t *gx_key_cache = NULL;
GX_UNUSED static uint64_t gx_key_cached = 0;
GX_UNUSED static uint64_t gx_cached_vertex_key(uint64_t vertex) {
    if (vertex >= gx_key_cached) {
        uint64_t count = 2 * gx_key_cached > vertex + 1 ? 2 * gx_key_cached : vertex + 1;
        uint64_t *grown = (uint64_t *)realloc(gx_key_cache, count * sizeof(uint64_t));
        if (!grown) return gx_vertex_key(vertex);
        for (uint64_t i = gx_key_cached; i < count; i++) grown[i] = gx_vertex_key(i);
        gx_key_cache = grown;
        gx_key_cached = count;
    }
    return gx_key_cache[vertex];
}

/* BLAKE2b-128, personalisation "vertex", of len <= 128 bytes */
static inline gx_u128 gx_blake2b_vertex_message(const uint8_t *message, unsigned len) {
    return gx_blake2b_128(message, len, 0x0000786574726576ULL);  /* "vertex" */
}

/* the fewest little-endian bytes of x > 0 written at out; their count */
static inline unsigned gx_le_bytes(uint64_t x, uint8_t *out) {
    unsigned n = 0;
    while (x) { out[n++] = (uint8_t)x; x >>= 8; }
    return n;
}

/* the trailing and leading zero bits of x != 0 */
static inline int gx_ctz64(uint64_t x) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctzll(x);
#else
    int n = 0;
    while (!(x & 1)) { x >>= 1; n++; }
    return n;
#endif
}
static inline int gx_clz64(uint64_t x) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_clzll(x);
#else
    int n = 0;
    while (!(x >> 63)) { x <<= 1; n++; }
    return n;
#endif
}

/* gmpy2.to_binary(mpq(g, 2**F)) written at out (at most 22 bytes), the fraction reduced
   by g's trailing zero bits: 0x03, the sign (0 zero, 1 positive, 2 negative), the
   numerator's byte count (u32, little-endian), the numerator's and the denominator's
   bytes; its length */
static inline unsigned gx_grid_to_binary(int64_t g, int F, uint8_t *out) {
    uint64_t magnitude, denominator;
    unsigned n;
    int t;
    out[0] = 0x03;
    if (g == 0) { out[1] = 0; return 2; }
    out[1] = g > 0 ? 1 : 2;
    magnitude = g > 0 ? (uint64_t)g : (uint64_t)0 - (uint64_t)g;
    t = gx_ctz64(magnitude);
    if (t > F) t = F;
    magnitude >>= t;
    denominator = (uint64_t)1 << (F - t);
    n = gx_le_bytes(magnitude, out + 6);
    out[2] = (uint8_t)n; out[3] = out[4] = out[5] = 0;
    return 6 + n + gx_le_bytes(denominator, out + 6 + n);
}

/* geomexact.kernel.digest.vertex_hash(vertex, (gx / 2**F, gy / 2**F)), 0 <= F <= 62 */
GX_UNUSED static gx_u128 gx_grid_vertex_hash(int64_t vertex, int64_t gx, int64_t gy, int F) {
    uint8_t message[64];
    unsigned len = 8;
    int k;
    for (k = 0; k < 8; k++) message[k] = (uint8_t)((uint64_t)vertex >> (8 * k));
    len += gx_grid_to_binary(gx, F, message + len);
    len += gx_grid_to_binary(gy, F, message + len);
    return gx_blake2b_vertex_message(message, len);
}

#endif /* GEOMEXACT_KERNEL_SUPPORT_H */
