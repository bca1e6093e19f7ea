/* Modified Cam-Clay as a UMAT (symbol = "mcc_umat"), written from the equations of the
 * built-in plugin plugins/cam_clay (README.md there; variant modified_cam_clay with a constant
 * shear modulus G and the closest-point return), to test that the adapter's TIME lets a UMAT
 * initialise its state once (plugins/umat/tests/test_umat_conventions.cpp).
 *
 * PROPS: M, lambda, kappa, e0, G (kPa), OCR, p_min (kPa).  STATEV(1) = p_c (kPa).
 * Tension positive; p = -tr(sigma) / 3 and q = sqrt(3 J2) compression positive; v0 = 1 + e0.
 *
 *   initial state  when TIME(2) = 0 (the first increment of the analysis, a common UMAT habit):
 *                  p_c = OCR (p + q^2 / (M^2 p)), p = max(p, p_min), from the committed stress
 *   elasticity     p = p_n + p_e (exp(x) - 1), x = -v0 tr(de_e) / kappa, p_e = max(p_n, p_min);
 *                  s = s_n + 2 G dev(de_e)
 *   yield          f = (q^2 / M^2 + p^2) / p_c - p
 *   flow           associated: de_p = dlambda df/dsigma, tr(de_p) = dlambda (1 - 2 p / p_c),
 *                  dev(de_p) = dlambda 3 s / (M^2 p_c)
 *   hardening      ln p_c = ln p_c,n + dlambda v0 / (lambda - kappa) (2 p / p_c - 1)
 *
 * The closest-point return (all at the end of the step) reduces with a constant G to three
 * scalar equations in p, xi = ln p_c and dlambda: s = s_trial / (1 + 6 G dlambda / (M^2 p_c)),
 * solved by Newton to round-off. A step is elastic when f(trial) <= 1e-9 p_c (the built-in's
 * ftol relative to its stress scale). DDSDDE by forward differences of the update. */
#include <math.h>
#include <stddef.h>
#include <string.h>

typedef struct {
  double M, lambda, kappa, v0, G, ocr, p_min;
} Constants;

static double mean_p(const double* s, int ndi) {
  double t = 0.0;
  for (int i = 0; i < ndi; ++i) t += s[i];
  return -t / 3.0;
}

static double mises_q(const double* s, int ndi, int n) {
  const double m = -mean_p(s, ndi);
  double ss = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double d = (i < ndi ? s[i] : 0.0) - m;
    ss += d * d;
  }
  for (int i = ndi; i < n; ++i) ss += 2.0 * s[i] * s[i];
  return sqrt(1.5 * ss);
}

/* The stress at the end of the increment de from the committed (s0, pc0); the new p_c in *pc. */
static void update(const Constants* c, int ndi, int n, const double* s0, double pc0, const double* de,
                   double* s, double* pc) {
  const double p0 = mean_p(s0, ndi), pe = p0 > c->p_min ? p0 : c->p_min;
  double tr = 0.0;
  for (int i = 0; i < ndi; ++i) tr += de[i];
  const double A = -c->v0 / c->kappa;
  /* elastic trial: deviator, then pressure */
  double dev[6];
  for (int i = 0; i < n; ++i) {
    const double d0 = s0[i] + (i < ndi ? p0 : 0.0);
    dev[i] = i < ndi ? d0 + 2.0 * c->G * (de[i] - tr / 3.0) : d0 + c->G * de[i];
  }
  const double p_tr = p0 + pe * expm1(A * tr);
  double tmp[6];
  for (int i = 0; i < n; ++i) tmp[i] = dev[i] - (i < ndi ? p_tr : 0.0);
  const double q_tr = mises_q(tmp, ndi, n), M2 = c->M * c->M;
  const double f_tr = (q_tr * q_tr / M2 + p_tr * p_tr) / pc0 - p_tr;
  if (f_tr <= 1e-9 * (pc0 > c->p_min ? pc0 : c->p_min)) {
    memcpy(s, tmp, sizeof(double) * (size_t)n);
    *pc = pc0;
    return;
  }
  /* plastic: Newton on R = (R_p, R_xi, R_f) in x = (p, xi, dlambda) */
  const double H = c->v0 / (c->lambda - c->kappa), k6 = 6.0 * c->G / M2, xi0 = log(pc0);
  double p = p_tr, xi = xi0, dl = 0.0;
  for (int it = 0; it < 100; ++it) {
    const double P = exp(xi), g = 1.0 - 2.0 * p / P, e = exp(A * (tr - dl * g));
    const double D = 1.0 + k6 * dl / P, q = q_tr / D;
    double R[3] = {p - p0 - pe * (e - 1.0), xi - xi0 - dl * H * (2.0 * p / P - 1.0),
                   (q * q / M2 + p * p) / P - p};
    double J[3][3];
    J[0][0] = 1.0 - pe * e * A * dl * 2.0 / P;
    J[0][1] = pe * e * A * dl * 2.0 * p / P;
    J[0][2] = pe * e * A * g;
    J[1][0] = -dl * H * 2.0 / P;
    J[1][1] = 1.0 + dl * H * 2.0 * p / P;
    J[1][2] = -H * (2.0 * p / P - 1.0);
    const double dfdq = 2.0 * q / (M2 * P);
    J[2][0] = 2.0 * p / P - 1.0;
    J[2][1] = -(q * q / M2 + p * p) / P + dfdq * q_tr * k6 * dl / (D * D * P);
    J[2][2] = -dfdq * q_tr * k6 / (D * D * P);
    /* solve J dx = -R (Cramer) */
    const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                       J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                       J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    double dx[3];
    for (int k = 0; k < 3; ++k) {
      double Jk[3][3];
      memcpy(Jk, J, sizeof J);
      for (int r = 0; r < 3; ++r) Jk[r][k] = -R[r];
      dx[k] = (Jk[0][0] * (Jk[1][1] * Jk[2][2] - Jk[1][2] * Jk[2][1]) -
               Jk[0][1] * (Jk[1][0] * Jk[2][2] - Jk[1][2] * Jk[2][0]) +
               Jk[0][2] * (Jk[1][0] * Jk[2][1] - Jk[1][1] * Jk[2][0])) /
              det;
    }
    p += dx[0], xi += dx[1], dl += dx[2];
    if (fabs(dx[0]) <= 1e-15 * fabs(p) && fabs(dx[1]) <= 1e-15 && fabs(dx[2]) <= 1e-15 * fabs(dl) + 1e-300)
      break;
  }
  const double P = exp(xi), D = 1.0 + k6 * dl / P;
  for (int i = 0; i < n; ++i) s[i] = dev[i] / D - (i < ndi ? p : 0.0);
  *pc = P;
}

void mcc_umat(double* STRESS, double* STATEV, double* DDSDDE, double* SSE, double* SPD, double* SCD,
              double* RPL, double* DDSDDT, double* DRPLDE, double* DRPLDT, double* STRAN, double* DSTRAN,
              double* TIME, double* DTIME, double* TEMP, double* DTEMP, double* PREDEF, double* DPRED,
              char* CMNAME, int* NDI, int* NSHR, int* NTENS, int* NSTATV, double* PROPS, int* NPROPS,
              double* COORDS, double* DROT, double* PNEWDT, double* CELENT, double* DFGRD0, double* DFGRD1,
              int* NOEL, int* NPT, int* LAYER, int* KSPT, int* KSTEP, int* KINC, size_t cmname_length) {
  (void)SSE, (void)SPD, (void)SCD, (void)RPL, (void)DDSDDT, (void)DRPLDE, (void)DRPLDT, (void)STRAN;
  (void)DTIME, (void)TEMP, (void)DTEMP, (void)PREDEF, (void)DPRED, (void)CMNAME, (void)NSHR, (void)NSTATV;
  (void)NPROPS, (void)COORDS, (void)DROT, (void)PNEWDT, (void)CELENT, (void)DFGRD0, (void)DFGRD1, (void)NOEL;
  (void)NPT, (void)LAYER, (void)KSPT, (void)KSTEP, (void)KINC, (void)cmname_length;
  const Constants c = {PROPS[0], PROPS[1], PROPS[2], 1.0 + PROPS[3], PROPS[4], PROPS[5], PROPS[6]};
  const int n = *NTENS, ndi = *NDI;
  if (TIME[1] == 0.0) { /* initialise from the stress of the first increment */
    double p = mean_p(STRESS, ndi);
    if (p < c.p_min) p = c.p_min;
    const double q = mises_q(STRESS, ndi, n);
    STATEV[0] = c.ocr * (p + q * q / (c.M * c.M * p));
  }
  double s0[6], s[6], pc;
  memcpy(s0, STRESS, sizeof(double) * (size_t)n);
  update(&c, ndi, n, s0, STATEV[0], DSTRAN, s, &pc);
  for (int j = 0; j < n; ++j) { /* forward differences */
    double de[6], sj[6], pcj;
    memcpy(de, DSTRAN, sizeof(double) * (size_t)n);
    const double h = 1e-9;
    de[j] += h;
    update(&c, ndi, n, s0, STATEV[0], de, sj, &pcj);
    for (int i = 0; i < n; ++i) DDSDDE[i + j * n] = (sj[i] - s[i]) / h;
  }
  memcpy(STRESS, s, sizeof(double) * (size_t)n);
  STATEV[0] = pc;
}
