/* A probe of the umat adapter's calling conventions (plugins/umat/tests/test_umat_conventions.cpp):
 * isotropic linear elasticity (PROPS(1) = E, PROPS(2) = nu) that also does what the material's
 * name (CMNAME) asks for:
 *
 *   CLOCK...      STATEV(1..10) = TIME(1), TIME(2), KSTEP, KINC, DTIME, COORDS(1), COORDS(2),
 *                 CELENT, the number of committed increments that saw TIME(2) = 0 (the habit of
 *                 initialising then: it must end as 1), DFGRD1(1,1) - 1 (NSTATV >= 10)
 *   OVERSTATEV... writes STATEV(1..9) whatever NSTATV is
 *   OVERPROPS...  writes PROPS(NPROPS + 1 .. NPROPS + 3)
 *   READPROPS...  reads PROPS(NPROPS + 1) as an extra stiffness term (a PROPS list too short)
 *   XIT...        calls XIT once TIME(2) >= 1 (from the second stage on)
 *
 * symbol = "probe_umat". The utility routine XIT comes from the adapter's library at load time. */
#include <stddef.h>
#include <string.h>

void xit_(void);

static int named(const char* cmname, const char* prefix) {
  return strncmp(cmname, prefix, strlen(prefix)) == 0;
}

void probe_umat(double* STRESS, double* STATEV, double* DDSDDE, double* SSE, double* SPD, double* SCD,
                double* RPL, double* DDSDDT, double* DRPLDE, double* DRPLDT, double* STRAN, double* DSTRAN,
                double* TIME, double* DTIME, double* TEMP, double* DTEMP, double* PREDEF, double* DPRED,
                char* CMNAME, int* NDI, int* NSHR, int* NTENS, int* NSTATV, double* PROPS, int* NPROPS,
                double* COORDS, double* DROT, double* PNEWDT, double* CELENT, double* DFGRD0, double* DFGRD1,
                int* NOEL, int* NPT, int* LAYER, int* KSPT, int* KSTEP, int* KINC, size_t cmname_length) {
  (void)SSE, (void)SPD, (void)SCD, (void)RPL, (void)DDSDDT, (void)DRPLDE, (void)DRPLDT, (void)STRAN;
  (void)TEMP, (void)DTEMP, (void)PREDEF, (void)DPRED, (void)DROT, (void)PNEWDT, (void)DFGRD0, (void)NOEL;
  (void)NPT, (void)LAYER, (void)KSPT, (void)NSHR, (void)cmname_length;
  const int n = *NTENS, ndi = *NDI;
  double E = PROPS[0];
  const double nu = PROPS[1];
  if (named(CMNAME, "READPROPS")) E += PROPS[*NPROPS]; /* past the end: the adapter's NaN */
  if (named(CMNAME, "XIT") && TIME[1] >= 1.0) xit_();
  const double G = E / (2.0 * (1.0 + nu)), lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  for (int i = 0; i < n * n; ++i) DDSDDE[i] = 0.0;
  for (int i = 0; i < ndi; ++i) {
    for (int j = 0; j < ndi; ++j) DDSDDE[i + j * n] = lam;
    DDSDDE[i + i * n] += 2.0 * G;
  }
  for (int i = ndi; i < n; ++i) DDSDDE[i + i * n] = G;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) STRESS[i] += DDSDDE[i + j * n] * DSTRAN[j];

  if (named(CMNAME, "CLOCK") && *NSTATV >= 10) {
    STATEV[0] = TIME[0];
    STATEV[1] = TIME[1];
    STATEV[2] = *KSTEP;
    STATEV[3] = *KINC;
    STATEV[4] = *DTIME;
    STATEV[5] = COORDS[0];
    STATEV[6] = COORDS[1];
    STATEV[7] = *CELENT;
    if (TIME[1] == 0.0) STATEV[8] += 1.0; /* the committed count plus this increment */
    STATEV[9] = DFGRD1[0] - 1.0;
  }
  if (named(CMNAME, "OVERSTATEV"))
    for (int i = 0; i < 9; ++i) STATEV[i] = i + 1.0;
  if (named(CMNAME, "OVERPROPS"))
    for (int i = 0; i < 3; ++i) PROPS[*NPROPS + i] = 0.0;
}
