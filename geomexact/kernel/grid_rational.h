/* mpq values of the dyadic grid, g / 2^F, built in place through gmpy2's C API (the
   capsule gmpy2._C_API: no link against GMP).  A grid value's reduced numerator and
   denominator each fit one 64-bit limb, so the new object's limbs are written directly,
   already canonical; this skips parsing two Python ints and a gcd in mpq(g, 2**F).

   Built with GX_WITH_GMPY2 (setup.py, when gmpy2's headers are found) and used only when
   the gmpy2 imported at run time is the version it was built against; otherwise
   gx_grid_mpq returns NULL and the caller builds the mpq in Python. */
#ifndef GEOMEXACT_GRID_RATIONAL_H
#define GEOMEXACT_GRID_RATIONAL_H

#include <Python.h>
#include <stdint.h>
#include <string.h>
#ifdef GX_WITH_GMPY2
#include "gmpy2.h"
#endif

static int gx_gmpy2_ready = 0;

/* the gmpy2 version whose headers this was built with, or "" */
static const char *gx_gmpy2_built_version(void) {
#ifdef GX_WITH_GMPY2
    return GX_GMPY2_VERSION;
#else
    return "";
#endif
}

/* 1 when the grid mpqs are built in C from now on, 0 when they are not (another gmpy2
   at run time, another limb size, no capsule); never raises */
static int gx_gmpy2_import(const char *runtime_version) {
#ifdef GX_WITH_GMPY2
    if (strcmp(runtime_version, GX_GMPY2_VERSION) != 0 || sizeof(mp_limb_t) != 8)
        return 0;
    if (import_gmpy2() < 0) {
        PyErr_Clear();
        return 0;
    }
    gx_gmpy2_ready = 1;
    return 1;
#else
    (void)runtime_version;
    return 0;
#endif
}

/* a new reference to mpq(g, 2**F), 0 <= F <= 62; NULL, with no exception set, when it
   is not built here (the caller builds it) */
static PyObject *gx_grid_mpq(int64_t g, int F) {
#ifdef GX_WITH_GMPY2
    MPQ_Object *result;
    mpz_ptr numerator, denominator;
    uint64_t magnitude;
    int t = 0;
    if (!gx_gmpy2_ready || F < 0 || F > 62) return NULL;
    result = GMPy_MPQ_New(NULL);
    if (!result) {
        PyErr_Clear();
        return NULL;
    }
    numerator = mpq_numref(result->q);
    denominator = mpq_denref(result->q);
    /* an initialised mpq has a limb for each part; not relying on it otherwise */
    if (numerator->_mp_alloc < 1 || denominator->_mp_alloc < 1) {
        Py_DECREF((PyObject *)result);
        return NULL;
    }
    if (g == 0) {
        numerator->_mp_size = 0;
        denominator->_mp_d[0] = 1;
        denominator->_mp_size = 1;
        return (PyObject *)result;
    }
    magnitude = g > 0 ? (uint64_t)g : (uint64_t)0 - (uint64_t)g;
    while (t < F && !(magnitude & 1)) { magnitude >>= 1; t++; }
    numerator->_mp_d[0] = (mp_limb_t)magnitude;
    numerator->_mp_size = g > 0 ? 1 : -1;
    denominator->_mp_d[0] = (mp_limb_t)((uint64_t)1 << (F - t));
    denominator->_mp_size = 1;
    return (PyObject *)result;
#else
    (void)g;
    (void)F;
    return NULL;
#endif
}

#endif /* GEOMEXACT_GRID_RATIONAL_H */
