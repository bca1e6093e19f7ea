/* Reference UMAT 3 (a Mohr-Coulomb-like soil for the loess-pile demonstration): Drucker-Prager
 * perfect plasticity on the cone through Mohr-Coulomb's triaxial-compression corners, with a
 * dilatancy angle (non-associated flow) and the closed-form apex return. Small strains.
 * Written for Stratum from the equations (de Souza Neto, Peric & Owen 2008, section 8.3; the
 * conventions of plugins/drucker_prager/README.md; no other UMAT was copied).
 *
 * Tension positive; Abaqus layout NDI = 3, then NSHR engineering shear strains; NTENS 4 or 6.
 *   alpha(x) = 2 sin x / (sqrt3 (3 - sin x)),  k = 6 cos phi / (sqrt3 (3 - sin phi))
 *   f = 3 alpha(phi) p + sqrt(J2) - k c,   g = 3 alpha(psi) p + sqrt(J2),   p = tr(sigma) / 3
 *   trial sigma_tr = sigma_n + D dstran;  dl = f_tr / (G + 9 K alpha alpha_psi)
 *   apex when f_tr > 0 and sqrt(J2_tr) - G dl < 0:  sigma = (k c / (3 alpha)) 1 (= c cot phi),
 *       d ep = sqrt(dl1^2 / 3 + 2 x^2 / 9),  dl1 = sqrt(J2_tr) / G,  x = (p_tr - c cot phi) / K;
 *       tangent 0 (perfect plasticity)
 *   elastic when f_tr <= 1e-9 max(k c, sqrt(J2_tr) + 3 alpha |p_tr|, 1e-9 G)
 *   cone:  s = (1 - G dl / sqrt(J2_tr)) s_tr,  p = p_tr - 3 K alpha_psi dl,
 *          d ep = dl sqrt(1/3 + 2 alpha_psi^2)
 *   consistent tangent (n = s_tr / |s_tr|, A = G + 9 K alpha alpha_psi, a = G dl / sqrt(J2_tr)):
 *     C = K 1x1 + 2 G (1 - a) I_dev + 2 G a n x n
 *         - (sqrt2 G n + 3 K alpha_psi 1) x (sqrt2 G n + 3 K alpha 1) / A
 *     (non-symmetric unless psi = phi)
 * PROPS: 1 E (kPa), 2 nu, 3 c (kPa), 4 phi (deg), 5 psi (deg, <= phi).
 * STATEV(1) = ep, the accumulated plastic strain sqrt(2/3) |d eps_p| (NSTATV >= 1).
 * Exported as "dp_umat"; Fortran calling convention (every argument by reference). */
#include <math.h>
#include <stddef.h>

void dp_umat(double* stress, double* statev, double* ddsdde, double* sse, double* spd, double* scd,
             double* rpl, double* ddsddt, double* drplde, double* drpldt, const double* stran,
             const double* dstran, const double* time, const double* dtime, const double* temp,
             const double* dtemp, const double* predef, const double* dpred, const char* cmname,
             const int* ndi, const int* nshr, const int* ntens, const int* nstatv, const double* props,
             const int* nprops, const double* coords, const double* drot, double* pnewdt,
             const double* celent, const double* dfgrd0, const double* dfgrd1, const int* noel,
             const int* npt, const int* layer, const int* kspt, const int* kstep, const int* kinc,
             size_t cmname_length) {
  (void)sse, (void)scd, (void)rpl, (void)ddsddt, (void)drplde, (void)drpldt, (void)stran, (void)time;
  (void)dtime, (void)temp, (void)dtemp, (void)predef, (void)dpred, (void)cmname, (void)nshr, (void)coords;
  (void)drot, (void)pnewdt, (void)celent, (void)dfgrd0, (void)dfgrd1, (void)noel, (void)npt, (void)layer;
  (void)kspt, (void)kstep, (void)kinc, (void)cmname_length;
  const int n = *ntens, nd = *ndi;
  if (*nprops < 5 || *nstatv < 1 || nd != 3) {
    for (int i = 0; i < n; ++i) stress[i] = NAN; /* misuse: the adapter reports a failed update */
    return;
  }
  const double deg = acos(-1.0) / 180.0;
  const double E = props[0], nu = props[1], c = props[2], sphi = sin(props[3] * deg),
               cphi = cos(props[3] * deg), spsi = sin(props[4] * deg);
  const double alpha = 2.0 * sphi / (sqrt(3.0) * (3.0 - sphi));
  const double alpha_psi = 2.0 * spsi / (sqrt(3.0) * (3.0 - spsi));
  const double k = 6.0 * cphi / (sqrt(3.0) * (3.0 - sphi));
  const double G = E / (2.0 * (1.0 + nu)), K = E / (3.0 * (1.0 - 2.0 * nu));
  const double lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));

  double tr[6];
  const double dev = dstran[0] + dstran[1] + dstran[2];
  for (int i = 0; i < n; ++i) tr[i] = stress[i];
  for (int i = 0; i < nd; ++i) tr[i] += lam * dev + 2.0 * G * dstran[i];
  for (int i = nd; i < n; ++i) tr[i] += G * dstran[i];
  const double p = (tr[0] + tr[1] + tr[2]) / 3.0;
  double s[6], ss = 0.0;
  for (int i = 0; i < n; ++i) {
    s[i] = i < nd ? tr[i] - p : tr[i];
    ss += i < nd ? s[i] * s[i] : 2.0 * s[i] * s[i];
  }
  const double sj = sqrt(0.5 * ss); /* sqrt(J2) */
  const double f = 3.0 * alpha * p + sj - k * c;
  const double A = G + 9.0 * K * alpha * alpha_psi;
  const double dl = f / A;

  for (int i = 0; i < n * n; ++i) ddsdde[i] = 0.0;
  if (f > 0.0 && sj - G * dl < 0.0) { /* apex */
    const double pa = k * c / (3.0 * alpha), dl1 = sj / G, x = (p - pa) / K;
    for (int i = 0; i < n; ++i) stress[i] = i < nd ? pa : 0.0;
    statev[0] += sqrt(dl1 * dl1 / 3.0 + 2.0 * x * x / 9.0);
    *spd += 0.0; /* sigma : d eps_p = pa x at the apex, kept out of SPD for simplicity */
    return;      /* tangent 0 */
  }
  double scale = k * c;
  if (sj + 3.0 * alpha * fabs(p) > scale) scale = sj + 3.0 * alpha * fabs(p);
  if (1e-9 * G > scale) scale = 1e-9 * G;
  if (f <= 1e-9 * scale) { /* elastic */
    for (int i = 0; i < n; ++i) stress[i] = tr[i];
    for (int i = 0; i < nd; ++i) {
      for (int j = 0; j < nd; ++j) ddsdde[i + j * n] = lam;
      ddsdde[i + i * n] = lam + 2.0 * G;
    }
    for (int i = nd; i < n; ++i) ddsdde[i + i * n] = G;
    return;
  }
  /* cone */
  const double a = G * dl / sj, norm = sqrt(ss), r2 = sqrt(2.0);
  double nv[6], u[6], v[6];
  for (int i = 0; i < n; ++i) {
    nv[i] = s[i] / norm;
    u[i] = r2 * G * nv[i] + (i < nd ? 3.0 * K * alpha_psi : 0.0); /* stress change direction */
    v[i] = r2 * G * nv[i] + (i < nd ? 3.0 * K * alpha : 0.0);     /* d f_tr / d eps */
    stress[i] = (1.0 - a) * s[i] + (i < nd ? p - 3.0 * K * alpha_psi * dl : 0.0);
  }
  statev[0] += dl * sqrt(1.0 / 3.0 + 2.0 * alpha_psi * alpha_psi);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double cij = 2.0 * G * a * nv[i] * nv[j] - u[i] * v[j] / A;
      if (i < nd && j < nd) cij += K + 2.0 * G * (1.0 - a) * ((i == j ? 1.0 : 0.0) - 1.0 / 3.0);
      if (i >= nd && i == j) cij += G * (1.0 - a);
      ddsdde[i + j * n] = cij;
    }
}
