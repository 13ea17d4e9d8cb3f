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
GX_UNUSED static int gx_map_grow(gx_map *m) {
    gx_map old = *m;
    if (gx_map_alloc(m, 2 * (old.mask + 1)) < 0) { *m = old; return -1; }
    for (uint64_t i = 0; i <= old.mask; i++) {
        if (old.keys[i] != GX_EMPTY) {
            uint64_t j = gx_map_slot(m, old.keys[i]);
            m->keys[j] = old.keys[i]; m->values[j] = old.values[i]; m->count++;
        }
    }
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

#endif /* GEOMEXACT_KERNEL_SUPPORT_H */
