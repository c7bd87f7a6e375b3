/*
 * rayproof/plugin.h: your ray intersection kernel as a shared library, put under rayproof's exact
 * differential test with `rayproof verify|report|fuzz --plugin NAME=PATH.so` (or `--plugin PATH.so`,
 * which takes the name the plugin declares).
 *
 * This header is C (C89 and later, and C++). It declares the one symbol a plugin exports:
 *
 *     RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void);
 *
 * which returns a pointer to a description that stays valid while the library is loaded (a static
 * const struct is the usual way). The description gives the kernel's name, its precision, and one
 * function per kind of primitive it answers.
 *
 * Inputs. A kind function receives the case's numbers in the order of docs/cases.md (the kind's fields
 * after the kind name: triangle o(3) d(3) p0(3) p1(3) p2(3), 15 numbers; plane 12, sphere 10,
 * ellipsoid 12, box 12, disk 13; tritri p0(3) p1(3) p2(3) q0(3) q1(3) q2(3), 18 numbers). A double kernel gets the doubles of the case file. A float kernel
 * gets each input rounded to nearest float, as floats; its t error is counted in float ulps and it
 * is judged against the exact answer on those rounded inputs. Inputs may be NaN or infinite (the
 * `invalid` family sends them).
 *
 * Answers. The same vocabulary as the line protocol (docs/kernel_protocol.md). The host sets
 * `cls` to RAYPROOF_NO_ANSWER and `has` to 0 before each call; the function then writes either
 *   - a full answer: `cls` one of the docs/cases.md classes RAYPROOF_INVALID .. RAYPROOF_RIM, with
 *     RAYPROOF_HAS_T / RAYPROOF_HAS_T2 in `has` for the values the class carries (`t`, `t2`), or
 *   - a coarse answer: `cls` RAYPROOF_COARSE_MISS (no contact at t >= 0; nothing in `has`) or
 *     RAYPROOF_COARSE_HIT, optionally with RAYPROOF_HAS_T (`t` = the first contact's t at t >= 0)
 *     and, for a triangle and together with RAYPROOF_HAS_T, RAYPROOF_HAS_B (`b1`, `b2` = the
 *     barycentrics of p1 and p2).
 * Anything else (no answer written, an unknown class or flag, T2 or barycentrics on a coarse answer,
 * barycentrics on a full one or on another kind) is a kernel failure for that case, reported with
 * the case as a one-line reproducer; it is not counted as a class error.
 *
 * Pairs of triangles. The function of RAYPROOF_KIND_TRITRI is the entry point for a triangle/
 * triangle test: it receives the two triangles (18 numbers, above) and writes RAYPROOF_COARSE_HIT
 * (they meet) or RAYPROOF_COARSE_MISS (they do not), or, if it knows the class, one of
 * RAYPROOF_DISJOINT .. RAYPROOF_COPLANAR_TOUCHING, RAYPROOF_INVALID or RAYPROOF_DEGENERATE; never
 * with values in `has`. A ray class for a pair, or a pair's class for a ray, is a kernel failure.
 * A pair kernel may answer ray kinds too. This kind was added in ABI version 1: plugins built
 * before it load unchanged; a rayproof older than it refuses a plugin declaring it ("bad kind 6").
 * examples/c_plugin/tritri_moller.c is a complete one.
 *
 * What the loader checks, refusing the plugin with a message otherwise: the library opens, exports
 * `rayproof_plugin_entry`, which returns a non-null description whose `abi_version` equals the
 * loader's RAYPROOF_PLUGIN_ABI_VERSION (checked before any other field is read), whose `name` is 1 to
 * 64 characters of [A-Za-z0-9_.+-], whose `precision` is RAYPROOF_FLOAT or RAYPROOF_DOUBLE, and whose
 * 1 to 7 kinds are distinct RAYPROOF_KIND_* values, each with the function of the declared precision.
 *
 * Threads. rayproof may call the kind functions from several threads at once (`fuzz --jobs`), so
 * they must not share mutable state without synchronisation. rayproof calls `rayproof_plugin_entry`
 * once per --plugin and never unloads the library.
 *
 * Crashes. In process (the default of verify, report, fuzz), a plugin that crashes takes rayproof
 * down with it. `rayproof plugin-host PATH.so` serves a plugin over the line protocol, so a plugin can
 * be run in a child process as an --exec kernel: `--exec NAME='rayproof plugin-host PATH.so'`.
 *
 * A minimal double triangle kernel:
 *
 *     #include <rayproof/plugin.h>
 *     static void triangle(const double *in, struct rayproof_answer *out) {
 *       ... out->cls = RAYPROOF_COARSE_HIT; out->t = t; out->has = RAYPROOF_HAS_T; ...
 *     }
 *     static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRIANGLE, triangle, 0}};
 *     static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "mine",
 *                                                  RAYPROOF_DOUBLE, 1, kinds};
 *     RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
 *
 * examples/c_plugin/moller_trumbore.c is a complete one.
 */
#ifndef RAYPROOF_PLUGIN_H
#define RAYPROOF_PLUGIN_H

/* The layout of the structs below. A loader refuses a plugin built against another version. */
#define RAYPROOF_PLUGIN_ABI_VERSION 1

/* The exported entry point's name, for dlsym. */
#define RAYPROOF_PLUGIN_ENTRY_NAME "rayproof_plugin_entry"

/* Precision. */
#define RAYPROOF_FLOAT 1
#define RAYPROOF_DOUBLE 2

/* Kinds (docs/cases.md). */
#define RAYPROOF_KIND_PLANE 0
#define RAYPROOF_KIND_SPHERE 1
#define RAYPROOF_KIND_ELLIPSOID 2
#define RAYPROOF_KIND_TRIANGLE 3
#define RAYPROOF_KIND_BOX 4
#define RAYPROOF_KIND_DISK 5
/* Two triangles, no ray (docs/tritri.md): 18 numbers, p0 p1 p2 of the first, q0 q1 q2 of the second. */
#define RAYPROOF_KIND_TRITRI 6

/* Full answers: the classes of docs/cases.md. */
#define RAYPROOF_INVALID 0
#define RAYPROOF_DEGENERATE 1
#define RAYPROOF_PARALLEL 2
#define RAYPROOF_COPLANAR 3
#define RAYPROOF_MISS 4
#define RAYPROOF_BEHIND 5
#define RAYPROOF_INTERIOR 6
#define RAYPROOF_EDGE 7
#define RAYPROOF_VERTEX 8
#define RAYPROOF_HIT 9
#define RAYPROOF_TANGENT 10
#define RAYPROOF_INSIDE 11
#define RAYPROOF_GRAZE 12
#define RAYPROOF_RIM 13

/* Full answers to a pair of triangles (RAYPROOF_KIND_TRITRI): the classes of docs/tritri.md, and
 * RAYPROOF_INVALID, RAYPROOF_DEGENERATE above. */
#define RAYPROOF_DISJOINT 15
#define RAYPROOF_CROSSING 16
#define RAYPROOF_TOUCHING 17
#define RAYPROOF_COPLANAR_OVERLAP 18
#define RAYPROOF_COPLANAR_TOUCHING 19

/* Coarse answers: only whether the ray touches the primitive at some t >= 0; for a pair of
 * triangles, whether they meet (share a point). */
#define RAYPROOF_COARSE_MISS 100
#define RAYPROOF_COARSE_HIT 101

/* What the host writes into `cls` before the call: left there, it is a kernel failure. */
#define RAYPROOF_NO_ANSWER (-1)

/* Bits of rayproof_answer.has: which values the answer carries. */
#define RAYPROOF_HAS_T 1
#define RAYPROOF_HAS_T2 2
#define RAYPROOF_HAS_B 4

struct rayproof_answer {
  int cls;   /* a class above (full) or RAYPROOF_COARSE_MISS / RAYPROOF_COARSE_HIT */
  int has;   /* RAYPROOF_HAS_* bits */
  double t;  /* full: T of the class; coarse hit: the first contact's t */
  double t2; /* full: T2 of the class */
  double b1; /* coarse triangle hit: barycentric of p1 */
  double b2; /* coarse triangle hit: barycentric of p2 */
};

typedef void (*rayproof_double_fn)(const double *in, struct rayproof_answer *out);
typedef void (*rayproof_float_fn)(const float *in, struct rayproof_answer *out);

/* One kind the kernel answers: set the function of the declared precision, leave the other 0. */
struct rayproof_kind_fn {
  int kind;                     /* RAYPROOF_KIND_* */
  rayproof_double_fn on_double; /* a RAYPROOF_DOUBLE kernel's function */
  rayproof_float_fn on_float;   /* a RAYPROOF_FLOAT kernel's function */
};

struct rayproof_plugin {
  int abi_version;                     /* RAYPROOF_PLUGIN_ABI_VERSION: first, and read first */
  const char *name;                    /* the method name when --plugin gives none */
  int precision;                       /* RAYPROOF_FLOAT or RAYPROOF_DOUBLE */
  int kind_count;                      /* 1 to 7 */
  const struct rayproof_kind_fn *kinds; /* kind_count entries */
};

/* Marks the entry point exported with C linkage (and default visibility under -fvisibility=hidden). */
#if defined(__GNUC__) || defined(__clang__)
#define RAYPROOF_PLUGIN_VISIBLE __attribute__((visibility("default")))
#else
#define RAYPROOF_PLUGIN_VISIBLE
#endif
#ifdef __cplusplus
#define RAYPROOF_PLUGIN_EXPORT extern "C" RAYPROOF_PLUGIN_VISIBLE
#else
#define RAYPROOF_PLUGIN_EXPORT RAYPROOF_PLUGIN_VISIBLE
#endif

typedef const struct rayproof_plugin *(*rayproof_plugin_entry_fn)(void);

#endif /* RAYPROOF_PLUGIN_H */
