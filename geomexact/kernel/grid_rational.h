/* mpq values of the dyadic grid, g / 2^F, built in place: a new object from gmpy2's C
   API (the capsule gmpy2._C_API) set by GMP's mpq_set_si to the reduced fraction
   (g / 2^t) / 2^(F - t), both parts one 64-bit limb, already canonical.  This skips
   parsing two Python ints and a gcd in mpq(g, 2**F).  mpq_set_si is looked up in the GMP
   that gmpy2 itself loaded (dlsym through gmpy2's module), so nothing links against GMP.

   Built with GX_WITH_GMPY2 (setup.py, when gmpy2's headers are found) and used only when
   the gmpy2 imported at run time is the version it was built against and mpq_set_si is
   found; otherwise gx_grid_mpq returns NULL and the caller builds the mpq in Python. */
#ifndef GEOMEXACT_GRID_RATIONAL_H
#define GEOMEXACT_GRID_RATIONAL_H

#include <Python.h>
#include <stdint.h>
#include <string.h>
#ifdef GX_WITH_GMPY2
#include <dlfcn.h>
#include "gmpy2.h"
typedef void (*gx_mpq_set_si_function)(mpq_ptr, long, unsigned long);
static gx_mpq_set_si_function gx_mpq_set_si = NULL;
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
static int gx_gmpy2_import(const char *runtime_version, const char *module_path) {
#ifdef GX_WITH_GMPY2
    void *module;
    if (strcmp(runtime_version, GX_GMPY2_VERSION) != 0 || sizeof(mp_limb_t) != 8
            || sizeof(long) != 8)
        return 0;
    /* the loaded gmpy2 module, and through it the GMP it depends on (kept open: the
       module stays loaded anyway) */
    module = dlopen(module_path, RTLD_LAZY | RTLD_NOLOAD);
    if (!module) return 0;
    gx_mpq_set_si = (gx_mpq_set_si_function)dlsym(module, "__gmpq_set_si");
    if (!gx_mpq_set_si) return 0;
    if (import_gmpy2() < 0) {
        PyErr_Clear();
        return 0;
    }
    gx_gmpy2_ready = 1;
    return 1;
#else
    (void)runtime_version;
    (void)module_path;
    return 0;
#endif
}

/* a new reference to mpq(g, 2**F), 0 <= F <= 62; NULL, with no exception set, when it
   is not built here (the caller builds it) */
static PyObject *gx_grid_mpq(int64_t g, int F) {
#ifdef GX_WITH_GMPY2
    MPQ_Object *result;
    uint64_t magnitude;
    int t = 0;
    if (!gx_gmpy2_ready || F < 0 || F > 62) return NULL;
    result = GMPy_MPQ_New(NULL);
    if (!result) {
        PyErr_Clear();
        return NULL;
    }
    if (g == 0) {
        gx_mpq_set_si(result->q, 0, 1);
        return (PyObject *)result;
    }
    magnitude = g > 0 ? (uint64_t)g : (uint64_t)0 - (uint64_t)g;
    while (t < F && !(magnitude & 1)) { magnitude >>= 1; t++; }
    /* g >> t is exact (2^t divides g) and fits a long, as g does */
    gx_mpq_set_si(result->q, (long)(g >> t), (unsigned long)1 << (F - t));
    return (PyObject *)result;
#else
    (void)g;
    (void)F;
    return NULL;
#endif
}

/* 1 when `value` is an mpq whose denominator is no power of two or is at least 2^64
   (read off its limbs), so it is off every grid 2^-F, F <= 62; 0 when that is not known
   (no gmpy2 C API, not an mpq, or a power of two below 2^64) */
static int gx_off_grid_denominator(PyObject *value) {
#ifdef GX_WITH_GMPY2
    mpz_srcptr denominator;
    if (!gx_gmpy2_ready || !MPQ_Check(value)) return 0;
    denominator = mpq_denref(MPQ(value));
    if (denominator->_mp_size != 1) return 1;
    return (denominator->_mp_d[0] & (denominator->_mp_d[0] - 1)) != 0;
#else
    (void)value;
    return 0;
#endif
}

#endif /* GEOMEXACT_GRID_RATIONAL_H */
