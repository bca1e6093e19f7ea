/* Reference UMAT 2 of the umat adapter's tests: von Mises plasticity with linear isotropic
 * hardening, small strains, backward-Euler radial return with the consistent tangent.
 * Written for Stratum from the equations (Simo & Hughes 1998, ch. 3; no other UMAT was copied).
 *
 * Layout: Abaqus' NDI = 3 direct components, then NSHR engineering shear strains (tensor shear
 * stresses); NTENS = 4 (plane strain, axisymmetry) or 6. Tension positive.
 *
 *   G = E / (2 (1 + nu)),  K = E / (3 (1 - 2 nu)),  lambda = K - 2 G / 3
 *   trial:   sigma_tr = sigma_n + D dstran,  s = dev(sigma_tr),  q = sqrt(3/2 s:s)
 *   yield:   f = q - (sigma_y + H ep_n);  elastic when f <= 1e-9 (sigma_y + H ep_n)
 *   return:  dl = f / (3 G + H),  s = (1 - 3 G dl / q) s_tr,  ep = ep_n + dl
 *   tangent: C = K 1x1 + 2 G theta (I - 1x1 / 3) - 2 G theta_bar n x n,  n = s_tr / |s_tr|,
 *            theta = 1 - 3 G dl / q,  theta_bar = 3 G / (3 G + H) - (1 - theta)
 *   (I maps engineering shear strain to shear stress with 1/2 on its shear diagonal.)
 *
 * PROPS: 1 E (kPa), 2 nu, 3 sigma_y (kPa), 4 H (kPa), and three switches for the tests:
 *   5 pnewdt_above: > 0: PNEWDT = 0.5 when some |DSTRAN(i)| exceeds it (a too-large step)
 *   6 nan_above:    > 0: a NaN is returned when some |STRAN(i) + DSTRAN(i)| exceeds it
 *   7 nan_where:    where that NaN goes: 0 STRESS, 1 DDSDDE, 2 STATEV
 * STATEV(1) = ep, the accumulated equivalent plastic strain (NSTATV >= 1).
 * SPD accumulates the plastic dissipation (sigma_y + H ep_mid) dl.
 *
 * Exported as "mises_umat" (so a scene sets symbol = "mises_umat"), Fortran calling
 * convention: every argument by reference, CMNAME's length last. */
#include <math.h>
#include <stddef.h>

void mises_umat(double* stress, double* statev, double* ddsdde, double* sse, double* spd, double* scd,
                double* rpl, double* ddsddt, double* drplde, double* drpldt, const double* stran,
                const double* dstran, const double* time, const double* dtime, const double* temp,
                const double* dtemp, const double* predef, const double* dpred, const char* cmname,
                const int* ndi, const int* nshr, const int* ntens, const int* nstatv, const double* props,
                const int* nprops, const double* coords, const double* drot, double* pnewdt,
                const double* celent, const double* dfgrd0, const double* dfgrd1, const int* noel,
                const int* npt, const int* layer, const int* kspt, const int* kstep, const int* kinc,
                size_t cmname_length) {
  (void)sse, (void)scd, (void)rpl, (void)ddsddt, (void)drplde, (void)drpldt, (void)time, (void)dtime;
  (void)temp, (void)dtemp, (void)predef, (void)dpred, (void)cmname, (void)nshr, (void)coords, (void)drot;
  (void)celent, (void)dfgrd0, (void)dfgrd1, (void)noel, (void)npt, (void)layer, (void)kspt, (void)kstep;
  (void)kinc, (void)cmname_length;
  const int n = *ntens, nd = *ndi;
  if (*nprops < 4 || *nstatv < 1 || nd != 3) {
    for (int i = 0; i < n; ++i) stress[i] = NAN; /* misuse: the adapter reports a failed update */
    return;
  }
  const double E = props[0], nu = props[1], sy = props[2], H = props[3];
  const double pnewdt_above = *nprops > 4 ? props[4] : 0.0;
  const double nan_above = *nprops > 5 ? props[5] : 0.0;
  const int nan_where = *nprops > 6 ? (int)props[6] : 0;
  const double G = E / (2.0 * (1.0 + nu)), K = E / (3.0 * (1.0 - 2.0 * nu));
  const double lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));

  double big_d = 0.0, big_e = 0.0;
  for (int i = 0; i < n; ++i) {
    if (fabs(dstran[i]) > big_d) big_d = fabs(dstran[i]);
    if (fabs(stran[i] + dstran[i]) > big_e) big_e = fabs(stran[i] + dstran[i]);
  }
  if (pnewdt_above > 0.0 && big_d > pnewdt_above) *pnewdt = 0.5;

  /* elastic trial */
  double tr[6];
  for (int i = 0; i < n; ++i) tr[i] = stress[i];
  const double dev = dstran[0] + dstran[1] + dstran[2];
  for (int i = 0; i < nd; ++i) tr[i] += lam * dev + 2.0 * G * dstran[i];
  for (int i = nd; i < n; ++i) tr[i] += G * dstran[i];

  const double p = (tr[0] + tr[1] + tr[2]) / 3.0;
  double s[6], ss = 0.0;
  for (int i = 0; i < n; ++i) {
    s[i] = i < nd ? tr[i] - p : tr[i];
    ss += i < nd ? s[i] * s[i] : 2.0 * s[i] * s[i];
  }
  const double q = sqrt(1.5 * ss);
  const double ep = statev[0], yield = sy + H * ep;
  const double f = q - yield;

  for (int i = 0; i < n * n; ++i) ddsdde[i] = 0.0;
  if (f <= 1e-9 * yield) {
    for (int i = 0; i < n; ++i) stress[i] = tr[i];
    for (int i = 0; i < nd; ++i) {
      for (int j = 0; j < nd; ++j) ddsdde[i + j * n] = lam;
      ddsdde[i + i * n] = lam + 2.0 * G;
    }
    for (int i = nd; i < n; ++i) ddsdde[i + i * n] = G;
  } else {
    const double dl = f / (3.0 * G + H);
    const double theta = 1.0 - 3.0 * G * dl / q;
    const double theta_bar = 3.0 * G / (3.0 * G + H) - (1.0 - theta);
    const double norm = sqrt(ss);
    double nv[6];
    for (int i = 0; i < n; ++i) {
      nv[i] = s[i] / norm;
      stress[i] = i < nd ? p + theta * s[i] : theta * s[i];
    }
    statev[0] = ep + dl;
    *spd += (sy + H * (ep + 0.5 * dl)) * dl;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double c = -2.0 * G * theta_bar * nv[i] * nv[j];
        if (i < nd && j < nd) c += K + 2.0 * G * theta * ((i == j ? 1.0 : 0.0) - 1.0 / 3.0);
        if (i >= nd && i == j) c += G * theta;
        ddsdde[i + j * n] = c;
      }
  }

  if (nan_above > 0.0 && big_e > nan_above) {
    if (nan_where == 1)
      ddsdde[0] = NAN;
    else if (nan_where == 2)
      statev[0] = NAN;
    else
      for (int i = 0; i < n; ++i) stress[i] = NAN;
  }
}
