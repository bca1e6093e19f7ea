/* Our implementations of the Abaqus utility routines of abaqus_utilities.h (conventions there
 * and in README.md, "Utility routines"). Written from the documented meaning of the arguments. */
#include "abaqus_utilities.h"

#include <math.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>

/* The one piece of mutable global state of Stratum (README.md, "XIT"): Abaqus gives XIT no
 * argument, so the only way back from it to the call of the UMAT is a per-thread jump target,
 * set by stratum_umat_guarded_call around each call and restored after it. Thread-local, so
 * concurrent UMAT calls on the element threads each have their own. */
static _Thread_local jmp_buf* xit_target = NULL;

int stratum_umat_guarded_call(void (*fn)(void*), void* arg) {
  jmp_buf here;
  jmp_buf* volatile outer = xit_target;
  if (setjmp(here) != 0) {
    xit_target = outer;
    return 1;
  }
  xit_target = &here;
  fn(arg);
  xit_target = outer;
  return 0;
}

void xit_(void) {
  if (xit_target != NULL) longjmp(*xit_target, 1);
  /* Only reachable when code outside a UMAT call of the adapter calls XIT. */
  fputs("stratum: XIT was called outside a UMAT call; the program ends\n", stderr);
  exit(2);
}

/* ---- tensors: S with NDI direct components (11, 22, 33) and NSHR shears (12, 13, 23) */

static const int shear_row[3] = {0, 0, 1};
static const int shear_col[3] = {1, 2, 2};

static void unpack(const double* s, int lstr, int ndi, int nshr, double t[3][3]) {
  const double f = lstr == 2 ? 0.5 : 1.0; /* engineering shear strain -> tensor component */
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i][j] = 0.0;
  for (int k = 0; k < ndi && k < 3; ++k) t[k][k] = s[k];
  for (int k = 0; k < nshr && k < 3; ++k) {
    const double v = f * s[ndi + k];
    t[shear_row[k]][shear_col[k]] = v;
    t[shear_col[k]][shear_row[k]] = v;
  }
}

static void pack(double t[3][3], int lstr, int ndi, int nshr, double* s) {
  const double f = lstr == 2 ? 2.0 : 1.0;
  for (int k = 0; k < ndi && k < 3; ++k) s[k] = t[k][k];
  for (int k = 0; k < nshr && k < 3; ++k) s[ndi + k] = f * t[shear_row[k]][shear_col[k]];
}

/* Eigenvalues (descending) and unit eigenvectors (columns of v) of a symmetric 3 x 3 matrix by
 * cyclic Jacobi rotations, which converge for every symmetric matrix (repeated eigenvalues
 * included) to round-off. */
static void eigen_symmetric(double a[3][3], double value[3], double v[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v[i][j] = i == j ? 1.0 : 0.0;
  double scale = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) scale += a[i][j] * a[i][j];
  for (int sweep = 0; sweep < 100; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off <= 1e-32 * scale || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        /* the rotation in the (p, q) plane that zeroes a[p][q] */
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        const double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) { /* a = a J */
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) { /* a = J^T a */
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) { /* v = v J */
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (a[order[j]][order[j]] > a[order[i]][order[i]]) {
        const int tmp = order[i];
        order[i] = order[j];
        order[j] = tmp;
      }
  double w[3][3];
  for (int k = 0; k < 3; ++k) {
    value[k] = a[order[k]][order[k]];
    for (int i = 0; i < 3; ++i) w[i][k] = v[i][order[k]];
  }
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) v[i][k] = w[i][k];
}

void sinv_(const double* stress, double* sinv1, double* sinv2, const int* ndi, const int* nshr) {
  double t[3][3];
  unpack(stress, 1, *ndi, *nshr, t);
  const double m = (t[0][0] + t[1][1] + t[2][2]) / 3.0;
  double ss = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double d = t[i][j] - (i == j ? m : 0.0);
      ss += d * d;
    }
  *sinv1 = m;
  *sinv2 = sqrt(1.5 * ss);
}

void sprinc_(const double* s, double* ps, const int* lstr, const int* ndi, const int* nshr) {
  double t[3][3], v[3][3];
  unpack(s, *lstr, *ndi, *nshr, t);
  eigen_symmetric(t, ps, v);
}

void sprind_(const double* s, double* ps, double* an, const int* lstr, const int* ndi, const int* nshr) {
  double t[3][3], v[3][3];
  unpack(s, *lstr, *ndi, *nshr, t);
  eigen_symmetric(t, ps, v);
  /* AN(K, I) (column-major): component I of the direction of PS(K) */
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) an[k + 3 * i] = v[i][k];
}

void rotsig_(const double* s, const double* r, double* sprime, const int* lstr, const int* ndi,
             const int* nshr) {
  double t[3][3], rt[3][3], out[3][3];
  unpack(s, *lstr, *ndi, *nshr, t);
  for (int i = 0; i < 3; ++i) /* rt = R t, R(i, j) at r[i + 3 j] */
    for (int j = 0; j < 3; ++j) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += r[i + 3 * k] * t[k][j];
      rt[i][j] = sum;
    }
  for (int i = 0; i < 3; ++i) /* out = R t R^T */
    for (int j = 0; j < 3; ++j) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += rt[i][k] * r[j + 3 * k];
      out[i][j] = sum;
    }
  pack(out, *lstr, *ndi, *nshr, sprime);
}
